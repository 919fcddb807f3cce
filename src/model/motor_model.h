// The constant part of the simulation (MuJoCo's mjModel idea): parameters plus everything
// precomputed from them. Built once; shared read-only by simulators and analyses.
#pragma once

#include "model/machine/contact.h"
#include "model/machine/effects.h"
#include "model/machine/mover.h"
#include "model/machine/stator.h"
#include "model/modal/modal_constants.h"
#include "model/parameters.h"

namespace swum {

// Mutable simulation data (model_spec §4 state y plus time and the drive phasor).
struct MotorState {
  double q1_m = 0.0;  // L1 modal coordinate (u_tip = -q1)
  double q1_dot_m_s = 0.0;
  double q2_m = 0.0;  // B2 modal coordinate (w_tip = gTv q2)
  double q2_dot_m_s = 0.0;
  double mover_position_m = 0.0;
  double mover_velocity_m_s = 0.0;
  double contact_deflection_m = 0.0;  // Jenkins element: tangential spring deflection delta
                                      // (F_T = k_t delta); always 0 with a rigid contact
  double time_s = 0.0;
  // Slow states of the thermal and wear effects (docs/discrepancy.md); stay 0 when disabled.
  double stator_temperature_rise_k = 0.0;  // over ambient
  double sliding_distance_m = 0.0;         // mover travel since the start of the session
  double drive_sin = 0.0;                  // sin(theta), theta = drive phase (V_A = V0 sin theta)
  double drive_cos = 1.0;                  // cos(theta)
};

// Commanded drive, changeable at any step.
struct DriveInput {
  double amplitude_v = 0.0;  // terminal voltage amplitude of each phase, V0 (zero-to-peak, V)
  double frequency_hz = 40000.0;
  double phase_deg = 90.0;  // phase of V_B ahead of V_A; the sign selects the direction
  double load_n = 0.0;      // external load force on the mover (opposes +y motion)
};

// Tangential contact law used by the solvers (from contact.tangential_stiffness_n_m and
// numerics.friction_solver).
enum class TangentialContact {
  rigid_projection,  // k_t = 0, Coulomb projection (kappa -> infinity)
  rigid_erf,         // k_t = 0, exact root of the implicit erf law
  jenkins,           // k_t > 0: spring k_t in series with a Coulomb slider (state delta)
};

// Everything one step needs, flattened (no indirection in the hot loop).
struct MotorCoefficients {
  StatorForceCoefficients stator;
  double m1_inv_per_kg = 0.0, c1_n_s_m = 0.0;
  double m2_inv_per_kg = 0.0, c2_n_s_m = 0.0;
  double g_n = 0.0, g_t = 0.0, g_tv = 0.0;
  double preload_n = 0.0, contact_stiffness_n_m = 0.0;
  double preload_constant_force_n = 0.0;  // gNP F_P (back_end_constant), else 0
  TangentialContact tangential = TangentialContact::rigid_projection;
  double tangential_stiffness_n_m = 0.0;           // k_t (0 = rigid)
  double slider_limit_per_normal_force_m_n = 0.0;  // mu_c / k_t: |delta| <= this * F_N
  GuideFrictionModel guide_model = GuideFrictionModel::smoothed_sign;
  double friction_coefficient = 0.0, kappa_s_per_m = 0.0;
  double mover_mass_inv_per_kg = 0.0, mover_damping_n_s_m = 0.0;
  GuideFrictionCoefficients guide;
  double drive_amplitude_per_volt = 0.0;
  double clamped_capacitance_f = 0.0;  // C0 of one phase (electrical.h)
  EffectCoefficients effects;          // thermal, wear, amplifier droop (simulator housekeeping)
};

class MotorModel {
 public:
  // Validates the parameters (throws ParameterError) and computes the constants from
  // with_static_effects(parameters); parameters() returns them as given.
  explicit MotorModel(const MotorParameters& parameters);

  [[nodiscard]] const MotorParameters& parameters() const { return parameters_; }
  [[nodiscard]] const ModalConstants& constants() const { return constants_; }
  [[nodiscard]] const MotorCoefficients& coefficients() const { return coefficients_; }
  [[nodiscard]] double time_step_s() const { return parameters_.numerics.time_step_ns * 1e-9; }

  // Rest state: q1 at the static preload equilibrium, everything else zero, phasor at 0.
  [[nodiscard]] MotorState rest_state(double time_s = 0.0) const;

  // Tip displacements (m): u_tip = phiL(L) q1 = -q1, w_tip = gTv q2.
  [[nodiscard]] static double tip_normal_m(const MotorState& s) { return -s.q1_m; }
  [[nodiscard]] double tip_tangential_m(const MotorState& s) const { return coefficients_.g_tv * s.q2_m; }

 private:
  MotorParameters parameters_;
  ModalConstants constants_;
  MotorCoefficients coefficients_;
};

}  // namespace swum
