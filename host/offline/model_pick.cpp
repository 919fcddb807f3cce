#include "offline/model_pick.h"

#include <algorithm>
#include <cmath>

#include "commands/command_error.h"

namespace swum::host {
namespace {

bool same(double a, double b) { return std::abs(a - b) < 1e-6 * std::max(1.0, std::abs(a)); }

}  // namespace

std::vector<CurveSample> curve_at(const std::vector<SweepRow>& rows, double amplitude_v, double load_n) {
  std::vector<CurveSample> curve;
  for (const SweepRow& r : rows) {
    if (!same(r.amplitude_v, amplitude_v) || !same(r.load_n, load_n)) continue;
    // A point the device never measured (watchdog hiccup, timeout) is a hole in the curve, not
    // a collapse of the resonance; a blow-up of the model or the motor is.
    if (!r.ok && !is_physical_failure(r)) continue;
    CurveSample s;
    s.frequency_hz = r.frequency_hz;
    s.ok = r.ok;
    s.speed_mm_s = r.speed_mm_s;
    s.spread_mm_s = r.speed_spread_mm_s;
    curve.push_back(s);
  }
  return curve;
}

std::vector<VoltagePick> pick_voltages(const std::vector<SweepRow>& rows, const std::vector<double>& voltages,
                                       const std::vector<double>& loads_n, const PickOptions& options,
                                       const std::string& source) {
  std::vector<VoltagePick> picks;
  for (double v : voltages) {
    for (double load_n : loads_n) {
      const auto curve = curve_at(rows, v, load_n);
      if (curve.empty()) {
        throw CommandError(source + ": no rows at " + std::to_string(v) + " V and " + std::to_string(load_n) + " N");
      }
      picks.push_back({v, pick_operating_point(curve, options), load_n});
    }
  }
  return picks;
}

}  // namespace swum::host
