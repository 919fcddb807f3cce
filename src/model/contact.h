// Stator/mover interface (MODEL_SPEC §2): normal force with separation (eq. 16) and the erf
// friction law (eqs. 21-22), plus the implicit friction solves of the fixed-step scheme (§10).
#pragma once

#include <cmath>

namespace swum {

// Eq. 16 with phiL(L) = -1: F_N = max(0, F_P + k_e u_tip), u_tip = -q1.
[[nodiscard]] inline double normal_force_n(double preload_n, double stiffness_n_m, double q1_m) {
  const double f = preload_n - stiffness_n_m * q1_m;
  return f > 0.0 ? f : 0.0;
}

// Eqs. 21-22: F_T = mu_c F_N erf(kappa v_rel), force on the mover; limit_n = mu_c F_N.
[[nodiscard]] inline double erf_friction_n(double limit_n, double kappa_s_per_m,
                                           double relative_velocity_m_s) {
  return limit_n * std::erf(kappa_s_per_m * relative_velocity_m_s);
}

// Implicit friction of one step: with v_rel = v_rel_star - compliance * F_T (compliance =
// dt (gT gTv / M2 + 1/m), m/s per N) and F_T = limit erf(kappa v_rel).
// Coulomb projection (kappa -> infinity): F_T = clip(v_rel_star / compliance, -limit, limit),
// i.e. stick (v_rel = 0) when the force needed to stop the slip is within the cone.
[[nodiscard]] inline double coulomb_projection_friction_n(double relative_velocity_star_m_s,
                                                          double compliance_m_s_per_n,
                                                          double limit_n) {
  const double f = relative_velocity_star_m_s / compliance_m_s_per_n;
  return f > limit_n ? limit_n : (f < -limit_n ? -limit_n : f);
}

// The exact root of v = v* - compliance limit erf(kappa v) (monotone; safeguarded Newton from
// a start left of the root, converging monotonically because erf is concave for v > 0).
// Returns F_T = (v* - v)/compliance. No allocation, no throw; at most 30 iterations.
[[nodiscard]] double erf_implicit_friction_n(double relative_velocity_star_m_s,
                                             double compliance_m_s_per_n, double limit_n,
                                             double kappa_s_per_m);

}  // namespace swum
