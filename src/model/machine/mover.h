// Mover on its linear guide, eqs. (23)-(25) (model_spec §3).
#pragma once

#include <cmath>

namespace swum {

// tanh(x) by its [7/6] Pade approximant clamped at +-1 (continuous, monotone, |error| < 1e-4;
// no libm call, so the dead zone / stick regime costs about the same per step as sliding).
[[nodiscard]] inline double clamped_tanh(double x) {
  if (x > 4.97) return 1.0;
  if (x < -4.97) return -1.0;
  if (x == 0.0) return 0.0;  // mover at rest: keeps the division off the critical path
  const double x2 = x * x;
  const double t = x * (135135.0 + x2 * (17325.0 + x2 * (378.0 + x2))) /
                   (135135.0 + x2 * (62370.0 + x2 * (3150.0 + 28.0 * x2)));
  return t > 1.0 ? 1.0 : (t < -1.0 ? -1.0 : t);
}

// sign(v) smoothed as tanh(v / width) (width = 0: exact sign).
[[nodiscard]] inline double smooth_sign(double v, double width) {
  if (!(width > 0.0)) return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0);
  return clamped_tanh(v / width);
}

struct GuideFrictionCoefficients {
  double coefficient = 0.0;             // mu_s
  double weight_n = 0.0;                // g m
  double sign_width_m_s = 0.0;          // smoothing of sign(v_m); 0 = exact sign
  double inverse_sign_width_s_m = 0.0;  // 1/width (0 when width = 0)
};

[[nodiscard]] inline GuideFrictionCoefficients make_guide_friction(double coefficient, double weight_n,
                                                                   double sign_width_m_s) {
  return {coefficient, weight_n, sign_width_m_s, sign_width_m_s > 0.0 ? 1.0 / sign_width_m_s : 0.0};
}

// Eqs. 24-25: f_max = sign(v_m) mu_s (F_N + g m);
// F_f = F_load - F_T if |F_T| < |f_max| + F_load (stuck: net force -c v_m), else -f_max.
[[nodiscard]] inline double guide_friction_n(const GuideFrictionCoefficients& g, double friction_force_n,
                                             double normal_force_n, double load_n, double mover_velocity_m_s) {
  // Multiplication by the inverse width keeps a division off the loop-carried v_m chain.
  const double sign = g.inverse_sign_width_s_m > 0.0 ? clamped_tanh(mover_velocity_m_s * g.inverse_sign_width_s_m)
                                                     : smooth_sign(mover_velocity_m_s, 0.0);
  const double f_max = sign * g.coefficient * (normal_force_n + g.weight_n);
  if (std::abs(friction_force_n) < std::abs(f_max) + load_n) return load_n - friction_force_n;
  return -f_max;
}

// Implicit Coulomb guide friction (guide_friction_model = implicit_coulomb, §11.9): the
// projection of one step. velocity_pred = mover velocity after every other force of the step,
// cap = dt mu_s (F_N + g m)/m (the largest velocity change guide friction can make). Stuck
// (returns exactly 0) when the guide friction can stop the mover, else slides with the full
// Coulomb force opposing the motion. The guide force is (result - velocity_pred) m/dt.
[[nodiscard]] inline double coulomb_guide_velocity_m_s(double velocity_pred_m_s, double cap_m_s) {
  if (velocity_pred_m_s > cap_m_s) return velocity_pred_m_s - cap_m_s;
  if (velocity_pred_m_s < -cap_m_s) return velocity_pred_m_s + cap_m_s;
  return 0.0;
}

// Continuous form of the same law for the reference ODE: F_f = -mu_s (F_N + g m) tanh(v_m/w)
// (w = guide_sign_smoothing_m_s; exact sign if 0). No "stuck" branch of eqs. 24-25.
[[nodiscard]] inline double coulomb_guide_friction_n(const GuideFrictionCoefficients& g, double normal_force_n,
                                                     double mover_velocity_m_s) {
  const double sign = g.inverse_sign_width_s_m > 0.0 ? clamped_tanh(mover_velocity_m_s * g.inverse_sign_width_s_m)
                                                     : smooth_sign(mover_velocity_m_s, 0.0);
  return -sign * g.coefficient * (normal_force_n + g.weight_n);
}

// Eq. 23: m v_m' + c v_m = F_T + F_f - F_load.
[[nodiscard]] inline double mover_acceleration_m_s2(double inverse_mass_per_kg, double damping_n_s_m,
                                                    double friction_force_n, double guide_force_n, double load_n,
                                                    double velocity_m_s) {
  return inverse_mass_per_kg * (friction_force_n + guide_force_n - load_n - damping_n_s_m * velocity_m_s);
}

}  // namespace swum
