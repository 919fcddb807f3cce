#include "offline/band_run.h"

#include <stdexcept>
#include <string>

#include "formats/number_format.h"
#include "offline/offline_sweep.h"
#include "offline/parallel_for.h"

namespace swum::host {

void check_band_grid(const BandGrid& grid, int jobs) {
  check_grid(OfflineGrid{grid.voltages, grid.frequencies_hz, grid.loads_n});
  if (grid.temperature_rises_k.empty()) throw std::invalid_argument("--temperature-rise-k: no values");
  for (double rise : grid.temperature_rises_k) {
    if (!(rise >= 0.0 && rise <= 300.0)) {
      throw std::invalid_argument("--temperature-rise-k: " + format_number(rise) + " is outside 0..300 K");
    }
  }
  if (!(grid.margin_hz >= 0.0 && grid.margin_hz <= 10000.0)) {
    throw std::invalid_argument("--margin-hz: must be within 0..10000");
  }
  if (jobs < 0 || jobs > 1024) throw std::invalid_argument("--jobs: must be within 0..1024 (0 = all cores)");
}

void check_band_thermal(const BandGrid& grid, const MotorParameters& parameters, const std::string& parameters_source) {
  if (parameters.effects.thermal.enabled) return;
  for (double rise : grid.temperature_rises_k) {
    if (rise != 0.0) {
      throw std::invalid_argument("--temperature-rise-k: " + format_number(rise) + " K needs the thermal effect, but " +
                                  parameters_source + " has [effects.thermal] enabled = false");
    }
  }
}

std::vector<BandRow> run_operating_band(const MotorModel& model, const BandGrid& grid, int jobs,
                                        const BandPointDone& point_done) {
  const auto threads = static_cast<unsigned>(std::max(jobs, 0));
  return operating_band(model, grid, make_parallel_for(threads), parallel_threads(threads), point_done);
}

}  // namespace swum::host
