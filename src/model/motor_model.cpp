#include "model/motor_model.h"

namespace swum {

MotorModel::MotorModel(const MotorParameters& parameters) : parameters_(parameters) {
  validate_parameters(parameters_, "MotorModel");
  const MotorParameters effective = with_static_effects(parameters_);
  constants_ = compute_modal_constants(effective);
  const auto& c = constants_;
  auto& k = coefficients_;
  k.stator = make_stator_force_coefficients(c, effective.stator);
  k.m1_inv_per_kg = 1.0 / c.m1_kg;
  k.c1_n_s_m = c.c1_n_s_m;
  k.m2_inv_per_kg = 1.0 / c.m2_kg;
  k.c2_n_s_m = c.c2_n_s_m;
  k.g_n = c.g_n;
  k.g_t = c.g_t;
  k.g_tv = c.g_tv;
  k.preload_n = effective.contact.preload_n;
  k.contact_stiffness_n_m = effective.contact.stiffness_n_m;
  k.friction_coefficient = effective.contact.friction_coefficient;
  k.preload_constant_force_n = c.g_np * effective.contact.preload_n;
  k.tangential_stiffness_n_m = effective.contact.tangential_stiffness_n_m;
  if (k.tangential_stiffness_n_m > 0.0) {
    k.tangential = TangentialContact::jenkins;
    k.slider_limit_per_normal_force_m_n = k.friction_coefficient / k.tangential_stiffness_n_m;
  } else {
    k.tangential = effective.numerics.friction_solver == FrictionSolver::erf_newton
                       ? TangentialContact::rigid_erf
                       : TangentialContact::rigid_projection;
  }
  k.guide_model = effective.mover.guide_friction_model;
  k.kappa_s_per_m = c.kappa_s_per_m;
  k.mover_mass_inv_per_kg = 1.0 / effective.mover.mass_kg;
  k.mover_damping_n_s_m = effective.mover.damping_n_s_m;
  k.guide = make_guide_friction(effective.mover.guide_friction_coefficient,
                                effective.mover.gravity_m_s2 * effective.mover.mass_kg,
                                effective.mover.guide_sign_smoothing_m_s);
  k.drive_amplitude_per_volt = c.drive_amplitude_per_volt;
  k.clamped_capacitance_f = effective.stator.clamped_capacitance_nf * 1e-9;
  k.effects = make_effect_coefficients(effective, c);
}

MotorState MotorModel::rest_state(double time_s) const {
  MotorState s;
  s.q1_m = constants_.static_q1_m;
  s.time_s = time_s;
  return s;
}

}  // namespace swum
