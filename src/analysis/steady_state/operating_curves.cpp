#include "analysis/steady_state/operating_curves.h"

#include <algorithm>
#include <cmath>

#include "analysis/steady_state/steady_state_batch.h"

namespace swum {

std::vector<CurvePoint> run_points(const MotorModel& model, const std::vector<OperatingPoint>& points) {
  const std::vector<SteadyStateResult> results = run_points_to_steady_state(model, points);
  std::vector<CurvePoint> curve;
  curve.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) curve.push_back({points[i], results[i]});
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

// The forward speed at each frequency (0 when the point diverged or did not move forward), all
// points in one batch.
std::vector<double> forward_speeds(const MotorModel& model, double amplitude_v, const std::vector<double>& frequencies,
                                   double load_n) {
  std::vector<OperatingPoint> points;
  for (double f : frequencies) {
    OperatingPoint p;
    p.amplitude_v = amplitude_v;
    p.frequency_hz = f;
    p.load_n = load_n;
    points.push_back(p);
  }
  std::vector<double> speeds;
  for (const SteadyStateResult& r : run_points_to_steady_state(model, points)) {
    speeds.push_back(r.diverged || !(r.speed_mm_s > 0.0) ? 0.0 : r.speed_mm_s);
  }
  return speeds;
}

SpeedPeak best_of(const MotorModel& model, double amplitude_v, const std::vector<double>& frequencies, double load_n) {
  SpeedPeak peak;
  const std::vector<double> speeds = forward_speeds(model, amplitude_v, frequencies, load_n);
  for (std::size_t i = 0; i < frequencies.size(); ++i) {
    if (!(speeds[i] > 0.0)) continue;
    if (!peak.found || speeds[i] > peak.speed_mm_s) peak = {frequencies[i], speeds[i], true};
  }
  return peak;
}

}  // namespace

SpeedPeak frequency_of_max_speed(const MotorModel& model, double amplitude_v, double start_hz, double stop_hz,
                                 double step_hz, double load_n) {
  std::vector<double> descending = evenly_spaced(start_hz, stop_hz, step_hz);
  std::reverse(descending.begin(), descending.end());
  // Every coarse point at once (independent runs from rest, in SIMD lanes), then the walk down.
  const std::vector<double> speeds = forward_speeds(model, amplitude_v, descending, load_n);
  SpeedPeak coarse;
  for (std::size_t i = 0; i < descending.size(); ++i) {
    const double speed = speeds[i];
    if (coarse.found && speed < 0.5 * coarse.speed_mm_s) break;  // collapsed below the peak
    if (speed > 0.0 && (!coarse.found || speed > coarse.speed_mm_s)) coarse = {descending[i], speed, true};
  }
  if (!coarse.found) return coarse;
  const double lo = std::max(start_hz, coarse.frequency_hz - step_hz);
  const double hi = std::min(stop_hz, coarse.frequency_hz + step_hz);
  const SpeedPeak fine = best_of(model, amplitude_v, evenly_spaced(lo, hi, step_hz / 4.0), load_n);
  return (fine.found && fine.speed_mm_s >= coarse.speed_mm_s) ? fine : coarse;
}

}  // namespace swum
