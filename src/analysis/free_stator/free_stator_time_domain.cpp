#include "analysis/free_stator/free_stator_time_domain.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "integrators/dormand_prince.h"

namespace swum {

void FreeStatorOde::derivative(double t, const Vector& x, Vector& dx) const {
  const double th = omega_rad_s * t;
  const double s = std::sin(th);
  const double c = std::cos(th);
  const double va = amplitude_v * s;
  const double vb = amplitude_v * (s * cos_phase + c * sin_phase);
  dx[0] = x[1];
  dx[1] = (modal_force_n(force.l1, x[0], va, vb) - c1_n_s_m * x[1]) / m1_kg;
  dx[2] = x[3];
  dx[3] = (modal_force_n(force.b2, x[2], va, vb) - c2_n_s_m * x[3]) / m2_kg;
}

FreeStatorAmplitudes simulate_free_stator(const ModalConstants& constants, const StatorParameters& stator,
                                          double amplitude_v, double frequency_hz, const std::array<double, 4>& initial,
                                          const FreeStatorRunOptions& options) {
  FreeStatorOde ode;
  ode.force = make_stator_force_coefficients(constants, stator);
  ode.m1_kg = constants.m1_kg;
  ode.c1_n_s_m = constants.c1_n_s_m;
  ode.m2_kg = constants.m2_kg;
  ode.c2_n_s_m = constants.c2_n_s_m;
  ode.amplitude_v = constants.drive_amplitude_per_volt * amplitude_v;
  ode.omega_rad_s = 2.0 * std::numbers::pi * frequency_hz;
  const double phase = options.phase_deg * std::numbers::pi / 180.0;
  ode.cos_phase = std::cos(phase);
  ode.sin_phase = std::sin(phase);

  DormandPrinceOptions<FreeStatorOde::Vector> opt;
  opt.relative_tolerance = options.relative_tolerance;
  const double w = ode.omega_rad_s;
  opt.absolute_tolerance = {1e-16, 1e-16 * w, 1e-16, 1e-16 * w};
  opt.max_step = 1.0 / (options.samples_per_cycle * frequency_hz);
  opt.initial_step = opt.max_step * 0.1;

  FreeStatorAmplitudes out;
  FreeStatorOde::Vector x = initial;
  auto none = [](double, const FreeStatorOde::Vector&) {};
  if (!integrate_dormand_prince(ode, 0.0, options.settle_s, x, opt, none).ok) return out;
  constexpr double inf = std::numeric_limits<double>::infinity();
  double lo[2] = {inf, inf}, hi[2] = {-inf, -inf}, sum[2] = {0.0, 0.0};
  double previous_t = options.settle_s;
  double previous_q[2] = {x[0], x[2]};
  auto observe = [&](double t, const FreeStatorOde::Vector& y) {
    const double q[2] = {y[0], y[2]};
    for (int k = 0; k < 2; ++k) {
      lo[k] = std::min(lo[k], q[k]);
      hi[k] = std::max(hi[k], q[k]);
      sum[k] += 0.5 * (q[k] + previous_q[k]) * (t - previous_t);
      previous_q[k] = q[k];
    }
    previous_t = t;
  };
  if (!integrate_dormand_prince(ode, options.settle_s, options.settle_s + options.window_s, x, opt, observe).ok) {
    return out;
  }
  out.ok = true;
  out.tip_normal_um = 0.5 * (hi[0] - lo[0]) * 1e6;
  out.tip_tangential_um = 0.5 * (hi[1] - lo[1]) * std::abs(constants.phi_b_tip) * 1e6;
  out.mean_q1_m = sum[0] / options.window_s;
  out.mean_q2_m = sum[1] / options.window_s;
  return out;
}

}  // namespace swum
