// Stator/mover interface (model_spec §2): normal force with separation (eq. 16) and the erf
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
[[nodiscard]] inline double erf_friction_n(double limit_n, double kappa_s_per_m, double relative_velocity_m_s) {
  return limit_n * std::erf(kappa_s_per_m * relative_velocity_m_s);
}

// Implicit friction of one step: with v_rel = v_rel_star - compliance * F_T (compliance =
// dt (gT gTv / M2 + 1/m), m/s per N) and F_T = limit erf(kappa v_rel).
// Coulomb projection (kappa -> infinity): F_T = clip(v_rel_star / compliance, -limit, limit),
// i.e. stick (v_rel = 0) when the force needed to stop the slip is within the cone.
[[nodiscard]] inline double coulomb_projection_friction_n(double relative_velocity_star_m_s,
                                                          double compliance_m_s_per_n, double limit_n) {
  const double f = relative_velocity_star_m_s / compliance_m_s_per_n;
  return f > limit_n ? limit_n : (f < -limit_n ? -limit_n : f);
}

// ---------------------------------------------------------------------------------------
// Jenkins element (calibration term, not in the paper): the stator tip is connected to a
// massless contact point through a tangential spring k_t; that point rubs on the mover with
// Coulomb friction. State: spring deflection delta (m). Force on the mover F_T = k_t delta,
// |k_t delta| <= mu_c F_N; stick: delta' = gTv q2' - v_m; slip: k_t delta = +-mu_c F_N;
// F_N = 0 => delta = 0.

// Spring force, safeguarded to the cone (delta is kept inside it by the return mapping).
[[nodiscard]] inline double jenkins_force_n(double stiffness_n_m, double deflection_m, double limit_n) {
  const double f = stiffness_n_m * deflection_m;
  return f > limit_n ? limit_n : (f < -limit_n ? -limit_n : f);
}

// Return mapping of one step (projection onto |delta| <= limit_m = mu_c F_N(t_n+1)/k_t):
// elastic trial delta + dt v_rel, clipped. Unconditionally stable w.r.t. friction.
[[nodiscard]] inline double jenkins_return_mapping_m(double deflection_m, double increment_m, double limit_m) {
  const double trial = deflection_m + increment_m;
  return trial > limit_m ? limit_m : (trial < -limit_m ? -limit_m : trial);
}

// Continuous (differential-inclusion) form for the reference ODE: the play operator
//   delta' = v_rel                       inside the cone (stick, elastic);
//   delta' = min(v_rel, limit')          on the upper face delta >= limit (slip, or sticking
//   delta' = max(v_rel, -limit')         on the lower face delta <= -limit  when v_rel points in)
//   delta' = 0                           in separation (limit = 0; delta is 0 there)
// with limit = mu_c F_N/k_t and limit' = mu_c F_N'/k_t. The slider is exact Coulomb: an
// erf-regularised slider (kappa = 3.6e6) differs only below ~1 um/s of slip but makes the ODE
// stiff (~4e11 1/s) in slip.
[[nodiscard]] inline double jenkins_deflection_rate_m_s(double deflection_m, double limit_m, double limit_rate_m_s,
                                                        double relative_velocity_m_s) {
  if (!(limit_m > 0.0)) return 0.0;
  if (deflection_m >= limit_m) {
    return relative_velocity_m_s < limit_rate_m_s ? relative_velocity_m_s : limit_rate_m_s;
  }
  if (deflection_m <= -limit_m) {
    return relative_velocity_m_s > -limit_rate_m_s ? relative_velocity_m_s : -limit_rate_m_s;
  }
  return relative_velocity_m_s;
}

// The exact root of v = v* - compliance limit erf(kappa v) (monotone; safeguarded Newton from
// a start left of the root, converging monotonically because erf is concave for v > 0).
// Returns F_T = (v* - v)/compliance. No allocation, no throw; at most 30 iterations.
[[nodiscard]] double erf_implicit_friction_n(double relative_velocity_star_m_s, double compliance_m_s_per_n,
                                             double limit_n, double kappa_s_per_m);

}  // namespace swum
