#include "commands/envelope_options.h"

#include "offline/band_run.h"
#include "output/value_lists.h"

namespace swum::host {

void add_envelope_options(CLI::App& sub, EnvelopeOptions& o) {
  sub.add_option("--amplitude-v", o.amplitude_v_list,
                 "terminal voltage amplitudes per phase, comma list (V, zero-to-peak)")
      ->required();
  sub.add_option("--load", o.load_list, "loads, comma list (N)")->capture_default_str();
  sub.add_option("--temperature-rise-k", o.rise_list,
                 "stator temperature rises over ambient, comma list (K, 0..300; other than 0 needs [effects.thermal])")
      ->capture_default_str();
  sub.add_option("--margin-hz", o.margin_hz, "minimum margin above the peak (Hz), as swum pick")->capture_default_str();
  sub.add_option("--frequency-hz", o.frequency_range,
                 "START:STOP:STEP (Hz); every chain runs it from STOP down to START (default: 41500 down to 38000 Hz "
                 "in 25 Hz steps)")
      ->capture_default_str();
}

BandGrid envelope_grid(const EnvelopeOptions& o, int jobs) {
  BandGrid grid;
  grid.voltages = parse_number_list(o.amplitude_v_list, "--amplitude-v");
  grid.loads_n = parse_number_list(o.load_list, "--load");
  grid.temperature_rises_k = parse_number_list(o.rise_list, "--temperature-rise-k");
  grid.frequencies_hz = parse_range_or_value(o.frequency_range, "--frequency-hz");
  grid.margin_hz = o.margin_hz;
  check_band_grid(grid, jobs);
  return grid;
}

}  // namespace swum::host
