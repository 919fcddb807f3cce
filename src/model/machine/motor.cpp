#include "model/machine/motor.h"

#include <cmath>
#include <numbers>

namespace swum {

namespace {

// Tangential force on the mover with the reference laws (erf or Jenkins spring).
double reference_friction_n(const MotorCoefficients& k, double fn, const MotorOde::Vector& x) {
  const double limit = k.friction_coefficient * fn;
  if (k.tangential == TangentialContact::jenkins) {
    return jenkins_force_n(k.tangential_stiffness_n_m, x[7], limit);
  }
  return erf_friction_n(limit, k.kappa_s_per_m, k.g_tv * x[3] - x[5]);
}

double reference_guide_n(const MotorCoefficients& k, double ft, double fn, double load_n, double v_m) {
  if (k.guide_model == GuideFrictionModel::implicit_coulomb) {
    return coulomb_guide_friction_n(k.guide, fn, v_m);
  }
  return guide_friction_n(k.guide, ft, fn, load_n, v_m);
}

}  // namespace

InterfaceForces MotorOde::forces(double t, const Vector& x) const {
  const DriveInput in = schedule_(t);
  InterfaceForces f;
  f.normal_n = normal_force_n(k_.preload_n, k_.contact_stiffness_n_m, x[0]);
  f.friction_n = reference_friction_n(k_, f.normal_n, x);
  f.guide_n = reference_guide_n(k_, f.friction_n, f.normal_n, in.load_n, x[5]);
  return f;
}

void MotorOde::derivative(double t, const Vector& x, Vector& dxdt) const {
  const DriveInput in = schedule_(t);
  const double v0 = k_.drive_amplitude_per_volt * in.amplitude_v;
  const double phase = in.phase_deg * std::numbers::pi / 180.0;
  const double va = v0 * std::sin(x[6]);
  const double vb = v0 * std::sin(x[6] + phase);
  const double fn = normal_force_n(k_.preload_n, k_.contact_stiffness_n_m, x[0]);
  const double ft = reference_friction_n(k_, fn, x);
  const double ff = reference_guide_n(k_, ft, fn, in.load_n, x[5]);
  dxdt[0] = x[1];
  dxdt[1] = k_.m1_inv_per_kg * (modal_force_n(k_.stator.l1, x[0], va, vb) + k_.g_n * fn + k_.preload_constant_force_n -
                                k_.c1_n_s_m * x[1]);
  dxdt[2] = x[3];
  dxdt[3] = k_.m2_inv_per_kg * (modal_force_n(k_.stator.b2, x[2], va, vb) - k_.g_t * ft - k_.c2_n_s_m * x[3]);
  dxdt[4] = x[5];
  dxdt[5] = mover_acceleration_m_s2(k_.mover_mass_inv_per_kg, k_.mover_damping_n_s_m, ft, ff, in.load_n, x[5]);
  dxdt[6] = 2.0 * std::numbers::pi * in.frequency_hz;
  if (k_.tangential == TangentialContact::jenkins) {
    const double limit = k_.slider_limit_per_normal_force_m_n * fn;
    // F_N' = -k_e q1' in contact.
    const double limit_rate = fn > 0.0 ? -k_.slider_limit_per_normal_force_m_n * k_.contact_stiffness_n_m * x[1] : 0.0;
    dxdt[7] = jenkins_deflection_rate_m_s(x[7], limit, limit_rate, k_.g_tv * x[3] - x[5]);
  } else {
    dxdt[7] = 0.0;
  }
}

MotorOde::Vector MotorOde::pack(const MotorState& s, double theta_rad) {
  return {s.q1_m,    s.q1_dot_m_s,          s.q2_m, s.q2_dot_m_s, s.mover_position_m, s.mover_velocity_m_s,
          theta_rad, s.contact_deflection_m};
}

void MotorOde::unpack(const Vector& x, double t, MotorState& s) {
  s.q1_m = x[0];
  s.q1_dot_m_s = x[1];
  s.q2_m = x[2];
  s.q2_dot_m_s = x[3];
  s.mover_position_m = x[4];
  s.mover_velocity_m_s = x[5];
  s.contact_deflection_m = x[7];
  s.time_s = t;
  s.drive_sin = std::sin(x[6]);
  s.drive_cos = std::cos(x[6]);
}

}  // namespace swum
