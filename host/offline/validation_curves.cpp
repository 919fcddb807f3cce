#include "offline/validation_curves.h"

#include <functional>
#include <future>
#include <utility>

#include "analysis/steady_state/operating_curves.h"
#include "analysis/steady_state/steady_state.h"

namespace swum::host {
namespace {

XyCurve speed_curve(const MotorModel& model, const std::vector<OperatingPoint>& points,
                    const std::function<double(const OperatingPoint&)>& x_of) {
  XyCurve curve;
  for (const CurvePoint& c : run_points(model, points)) {
    if (c.result.diverged) continue;
    curve.x.push_back(x_of(c.point));
    curve.y.push_back(c.result.speed_mm_s);
  }
  return curve;
}

// Every voltage here is on the paper's axis (the figures' "Vpp"); the model runs at the terminal
// amplitude its options.paper_voltage_axis reads from it.
double amplitude_v(const MotorModel& model, double paper_v) {
  return amplitude_v_of_paper_voltage(model.parameters().options.paper_voltage_axis, paper_v);
}

std::vector<OperatingPoint> grid(const MotorModel& model, const std::vector<double>& paper_vs,
                                 const std::vector<double>& frequencies, const std::vector<double>& loads) {
  std::vector<OperatingPoint> points;
  for (double v : paper_vs)
    for (double f : frequencies)
      for (double l : loads) points.push_back({amplitude_v(model, v), f, l, 90.0});
  return points;
}

double by_khz(const OperatingPoint& p) { return p.frequency_hz / 1000.0; }
double by_load(const OperatingPoint& p) { return p.load_n; }

// Fig. 14: the non-linear curves on their own threads while the linear ones run here.
std::vector<FrequencyCurves> speed_vs_frequency(const MotorModel& nl, const MotorModel& lin) {
  std::vector<FrequencyCurves> curves;
  std::vector<std::future<XyCurve>> futures;
  for (double paper_v : {100.0, 250.0, 400.0}) {
    const auto points = grid(nl, {paper_v}, evenly_spaced(39000, 41000, 50), {0});
    futures.push_back(std::async(std::launch::async, [&nl, points] { return speed_curve(nl, points, by_khz); }));
    curves.push_back({paper_v, {}, speed_curve(lin, points, by_khz)});
  }
  for (std::size_t i = 0; i < curves.size(); ++i) curves[i].nonlinear = futures[i].get();
  return curves;
}

void peak_vs_voltage(PaperFacts& facts, const MotorModel& nl, const MotorModel& lin, ValidationCurves& out) {
  for (double paper_v : evenly_spaced(50, 400, 50)) {
    const SpeedPeak p = facts.peak(nl, paper_v);
    if (p.found) {
      out.peak_vs_voltage_nonlinear.x.push_back(paper_v);
      out.peak_vs_voltage_nonlinear.y.push_back(p.frequency_hz / 1000.0);
    }
    const SpeedPeak q = facts.peak(lin, paper_v);
    if (q.found) {
      out.peak_vs_voltage_linear.x.push_back(paper_v);
      out.peak_vs_voltage_linear.y.push_back(q.frequency_hz / 1000.0);
    }
  }
}

// Free stator (mover removed: no preload, no contact), last drive period of a 30 ms run.
TipOrbit tip_orbit(const MotorModel& free_stator, double paper_v, double frequency_hz) {
  SteadyStateOptions options;
  options.settle_s = 0.030;
  options.window_s = 1.0 / frequency_hz;
  options.max_s = options.settle_s + options.window_s;
  options.speed_tolerance_mm_s = 1e300;
  options.trace_every_steps = 1;
  TipOrbit orbit{paper_v, frequency_hz, {}};
  const double from_s = options.settle_s;
  options.trace = [&orbit, from_s](const TraceSample& s) {
    if (s.time_s < from_s) return;
    orbit.tip_um.x.push_back(s.tip_tangential_um);
    orbit.tip_um.y.push_back(s.tip_normal_um);
  };
  (void)run_to_steady_state(free_stator, {amplitude_v(free_stator, paper_v), frequency_hz, 0.0, 90.0}, options);
  return orbit;
}

}  // namespace

ValidationCurves validation_curves(const MotorParameters& parameters, const MotorModel& nonlinear,
                                   const MotorModel& linear, PaperFacts& facts) {
  ValidationCurves out;

  const auto by_voltage = grid(nonlinear, evenly_spaced(0, 400, 25), {40000}, {0});
  const double amplitude_per_paper_v = amplitude_v(nonlinear, 1.0);
  const auto by_paper_v = [amplitude_per_paper_v](const OperatingPoint& p) {
    return p.amplitude_v / amplitude_per_paper_v;
  };
  auto nl_future = std::async(std::launch::async, [&] { return speed_curve(nonlinear, by_voltage, by_paper_v); });
  out.speed_vs_voltage_linear = speed_curve(linear, by_voltage, by_paper_v);
  out.speed_vs_voltage_nonlinear = nl_future.get();

  out.speed_vs_frequency = speed_vs_frequency(nonlinear, linear);
  peak_vs_voltage(facts, nonlinear, linear, out);

  const std::vector<double> loads = evenly_spaced(0, 6, 0.5);
  for (auto [paper_v, f] : {std::pair{300.0, 40060.0}, {300.0, 40400.0}, {400.0, 39600.0}, {400.0, 40400.0}}) {
    out.speed_vs_load.push_back({paper_v, f, speed_curve(nonlinear, grid(nonlinear, {paper_v}, {f}, loads), by_load)});
  }

  MotorParameters free = parameters;
  free.contact.preload_n = 0.0;
  free.contact.stiffness_n_m = 0.0;
  const MotorModel free_stator(free);
  for (double paper_v : {100.0, 200.0, 300.0, 400.0})
    out.orbit_vs_voltage.push_back(tip_orbit(free_stator, paper_v, 39500));
  for (double f : {39000.0, 39200.0, 39500.0}) out.orbit_vs_frequency.push_back(tip_orbit(free_stator, 400, f));
  return out;
}

}  // namespace swum::host
