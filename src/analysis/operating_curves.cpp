#include "analysis/operating_curves.h"

#include <algorithm>
#include <cmath>

namespace swum {

std::vector<CurvePoint> run_points(const MotorModel& model, const std::vector<OperatingPoint>& points) {
  std::vector<CurvePoint> curve;
  curve.reserve(points.size());
  for (const OperatingPoint& p : points) curve.push_back({p, run_to_steady_state(model, p)});
  return curve;
}

std::vector<double> evenly_spaced(double start, double stop, double step) {
  std::vector<double> values;
  if (!(step > 0.0) || stop < start) return values;
  const auto count = static_cast<std::size_t>(std::floor((stop - start) / step + 1e-6)) + 1;
  values.reserve(count);
  for (std::size_t i = 0; i < count; ++i) values.push_back(start + static_cast<double>(i) * step);
  return values;
}

namespace {

SpeedPeak best_of(const MotorModel& model, double vpp, const std::vector<double>& frequencies, double load_n) {
  SpeedPeak peak;
  for (double f : frequencies) {
    OperatingPoint p;
    p.vpp = vpp;
    p.frequency_hz = f;
    p.load_n = load_n;
    const SteadyStateResult r = run_to_steady_state(model, p);
    if (r.diverged || !(r.speed_mm_s > 0.0)) continue;
    if (!peak.found || r.speed_mm_s > peak.speed_mm_s) peak = {f, r.speed_mm_s, true};
  }
  return peak;
}

}  // namespace

SpeedPeak frequency_of_max_speed(const MotorModel& model, double vpp, double start_hz, double stop_hz, double step_hz,
                                 double load_n) {
  std::vector<double> descending = evenly_spaced(start_hz, stop_hz, step_hz);
  std::reverse(descending.begin(), descending.end());
  SpeedPeak coarse;
  for (double f : descending) {
    const SpeedPeak here = best_of(model, vpp, {f}, load_n);
    const double speed = here.found ? here.speed_mm_s : 0.0;
    if (coarse.found && speed < 0.5 * coarse.speed_mm_s) break;  // collapsed below the peak
    if (here.found && (!coarse.found || speed > coarse.speed_mm_s)) coarse = here;
  }
  if (!coarse.found) return coarse;
  const double lo = std::max(start_hz, coarse.frequency_hz - step_hz);
  const double hi = std::min(stop_hz, coarse.frequency_hz + step_hz);
  const SpeedPeak fine = best_of(model, vpp, evenly_spaced(lo, hi, step_hz / 4.0), load_n);
  return (fine.found && fine.speed_mm_s >= coarse.speed_mm_s) ? fine : coarse;
}

}  // namespace swum
