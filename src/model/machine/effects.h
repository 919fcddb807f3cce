// The time-domain part of the candidate effects (docs/discrepancy.md): the slow states
// (stator temperature, sliding distance) and the amplifier droop, evaluated by
// MotorSimulator once per housekeeping block (64 steps), never in the per-step hot path.
// Electroelastic, preload and guide-friction effects are folded into the constant model
// (with_static_effects, parameters.h).
#pragma once

#include <cmath>

#include "model/machine/output_network.h"
#include "model/modal/modal_constants.h"
#include "model/parameters.h"

namespace swum {

struct EffectCoefficients {
  bool thermal = false;
  double thermal_resistance_k_per_w = 0.0;
  double inverse_time_constant_per_s = 0.0;
  double stiffness_per_k = 0.0;
  double damping_per_k = 0.0;

  bool wear = false;
  double friction_change = 0.0;
  double inverse_run_in_distance_per_m = 0.0;

  // The droop effect alone (no [amplifier] network): the magnitude-only gain, mean of the two
  // phases, that the SIMD lanes also run (BatchSimulator).
  bool droop = false;
  double source_resistance_ohm = 0.0;
  double clamped_capacitance_f = 0.0;
  // The [amplifier] output network (output_network.h), per phase in magnitude and phase; the droop
  // effect's R_s, when it is on, is in its source resistance (and droop is then false).
  bool network = false;
  OutputNetwork output_network;
  // Motional charge per modal displacement of phase A and B (C/m) on q1 and q2: by
  // reciprocity the linear modal force per volt a0, b0 of eqs. 14-15.
  double charge_a_q1 = 0.0, charge_a_q2 = 0.0;
  double charge_b_q1 = 0.0, charge_b_q2 = 0.0;

  [[nodiscard]] bool any() const { return thermal || wear || droop || network; }
  [[nodiscard]] bool slow() const { return thermal || wear; }
};

[[nodiscard]] EffectCoefficients make_effect_coefficients(const MotorParameters& parameters,
                                                          const ModalConstants& constants);

// Thermal effect: K_i -> K_i * stiffness, C_i -> C_i * damping at temperature rise T.
struct ThermalFactors {
  double stiffness = 1.0;
  double damping = 1.0;
};
[[nodiscard]] inline ThermalFactors thermal_factors(const EffectCoefficients& e, double temperature_rise_k) {
  if (!e.thermal) return {};
  return {1.0 + e.stiffness_per_k * temperature_rise_k, 1.0 + e.damping_per_k * temperature_rise_k};
}

// dT/dt = (R_th P - T)/tau over `duration_s` at constant power: exact exponential step.
[[nodiscard]] inline double thermal_step_k(const EffectCoefficients& e, double temperature_rise_k, double power_w,
                                           double duration_s) {
  const double target = e.thermal_resistance_k_per_w * power_w;
  return target + (temperature_rise_k - target) * std::exp(-duration_s * e.inverse_time_constant_per_s);
}

// Wear effect: mu_c(s) / mu_c = 1 + d (1 - exp(-s/s0)) (clamped at 0).
[[nodiscard]] inline double wear_friction_factor(const EffectCoefficients& e, double sliding_distance_m) {
  if (!e.wear) return 1.0;
  const double f = 1.0 + e.friction_change * (1.0 - std::exp(-sliding_distance_m * e.inverse_run_in_distance_per_m));
  return f > 0.0 ? f : 0.0;
}

// Modal displacement about its static value -> analytic signal q - j q'/w (valid for a
// sinusoid at w; the projection of the state on the drive harmonic).
struct Analytic {
  double re = 0.0;
  double im = 0.0;
};

// Amplifier droop: ratio of the drive amplitude at the piezo to the commanded one, mean of
// the two phases: V = (V_cmd - R_s I_m)/(1 + j w R_s C0), I_m = j w (Q_q1 q1 + Q_q2 q2)
// (analytic signals), the output network's terminal voltage (OutputNetwork{R_s, 0, 0, C0}) in
// magnitude only. Returns 1/|1 + j w R_s C0| when there is no drive.
[[nodiscard]] double droop_gain(const EffectCoefficients& e, double angular_frequency_rad_s, double sin_theta,
                                double cos_theta, double cos_phase, double sin_phase, double amplitude_v, Analytic q1,
                                Analytic q2);
// The same with the two phases commanded at their own amplitudes (run-time phase faults,
// model_faults.h): the mean over the driven phases (amplitude > 0); equal amplitudes give
// exactly the value above.
[[nodiscard]] double droop_gain(const EffectCoefficients& e, double angular_frequency_rad_s, double sin_theta,
                                double cos_theta, double cos_phase, double sin_phase, double amplitude_a_v,
                                double amplitude_b_v, Analytic q1, Analytic q2);

}  // namespace swum
