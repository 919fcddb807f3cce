// Fuzz target: the free-stator amplitude CSV reader of `swum identify` (host/output/amplitude_csv.h).
// Input: byte 0 = the minimum number of amplitude values asked for (0..7), the rest the file.
// Invariants: the only error is CommandError; accepted rows have finite values, amplitude_v >= 0,
// frequency > 0, non-negative amplitudes, at least one amplitude each and at least the asked
// number in total; writing them (format_amplitude_csv) gives a file the reader accepts and that
// writes back identically.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "commands/command_error.h"
#include "fuzz_check.h"
#include "output/amplitude_csv.h"

using swum::AmplitudeMeasurement;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const int min_amplitudes = data[0] & 7;
  const std::string_view text = swum::fuzz::as_text(data + 1, size - 1);
  std::vector<AmplitudeMeasurement> rows;
  try {
    rows = swum::host::parse_amplitude_csv(text, "fuzz.csv", min_amplitudes);
  } catch (const swum::host::CommandError&) {
    return 0;
  }
  int amplitudes = 0;
  for (const AmplitudeMeasurement& m : rows) {
    FUZZ_CHECK(std::isfinite(m.amplitude_v) && m.amplitude_v >= 0.0, "amplitude_v %g", m.amplitude_v);
    FUZZ_CHECK(std::isfinite(m.frequency_hz) && m.frequency_hz > 0.0, "frequency %g", m.frequency_hz);
    FUZZ_CHECK(m.tip_normal_um || m.tip_tangential_um, "row %d without an amplitude", m.source_line);
    for (const auto& v : {m.tip_normal_um, m.tip_tangential_um}) {
      if (v) FUZZ_CHECK(std::isfinite(*v) && *v >= 0.0, "amplitude %g", *v);
      amplitudes += v ? 1 : 0;
    }
  }
  FUZZ_CHECK(amplitudes >= min_amplitudes, "%d amplitudes, %d asked for", amplitudes, min_amplitudes);
  const std::string written = swum::host::format_amplitude_csv(rows);
  std::vector<AmplitudeMeasurement> again;
  try {
    again = swum::host::parse_amplitude_csv(written, "written.csv", min_amplitudes);
  } catch (const swum::host::CommandError& e) {
    FUZZ_CHECK(false, "the written file is refused: %s\n%s", e.what(), written.c_str());
  }
  FUZZ_CHECK(again.size() == rows.size(), "%zu rows written, %zu read back", rows.size(), again.size());
  FUZZ_CHECK(swum::host::format_amplitude_csv(again) == written, "writing what was read back differs");
  return 0;
}
