#include "model/machine/effects.h"

namespace swum {

EffectCoefficients make_effect_coefficients(const MotorParameters& p, const ModalConstants& c) {
  EffectCoefficients e;
  const EffectParameters& x = p.effects;
  if (x.thermal.enabled) {
    e.thermal = true;
    e.thermal_resistance_k_per_w = x.thermal.thermal_resistance_k_per_w;
    e.inverse_time_constant_per_s = 1.0 / x.thermal.time_constant_s;
    e.stiffness_per_k = x.thermal.stiffness_coefficient_per_k;
    e.damping_per_k = x.thermal.damping_coefficient_per_k;
  }
  if (x.wear.enabled) {
    e.wear = true;
    e.friction_change = x.wear.friction_change;
    e.inverse_run_in_distance_per_m = 1.0 / x.wear.run_in_distance_m;
  }
  const AmplifierParameters& amplifier = p.amplifier;
  const bool network = amplifier.source_resistance_ohm != 0.0 || amplifier.series_inductance_uh != 0.0 ||
                       amplifier.parallel_inductance_uh != 0.0;
  if (network) {
    e.network = true;
    e.output_network = make_output_network(p);  // with the droop effect's R_s when it is on
  } else if (x.amplifier_droop.enabled) {
    e.droop = true;
    e.source_resistance_ohm = x.amplifier_droop.source_resistance_ohm;
    e.clamped_capacitance_f = p.stator.clamped_capacitance_nf * 1e-9;  // the electrical port's C0
  }
  // Always: the amplifier readings of an ideal source need them too (MotorSimulator::amplifier_readings).
  e.charge_a_q1 = c.a[0].group_a;
  e.charge_a_q2 = c.b[0].group_a;
  e.charge_b_q1 = c.a[0].group_b;
  e.charge_b_q2 = c.b[0].group_b;
  return e;
}

double droop_gain(const EffectCoefficients& e, double w, double s, double c, double cos_phase, double sin_phase,
                  double amplitude_v, Analytic q1, Analytic q2) {
  return droop_gain(e, w, s, c, cos_phase, sin_phase, amplitude_v, amplitude_v, q1, q2);
}

double droop_gain(const EffectCoefficients& e, double w, double s, double c, double cos_phase, double sin_phase,
                  double amplitude_a_v, double amplitude_b_v, Analytic q1, Analytic q2) {
  // The output network of a source resistance alone: V = (V_cmd - R_s I_m)/(1 + j w R_s C0).
  const OutputNetwork network{e.source_resistance_ohm, 0.0, 0.0, e.clamped_capacitance_f};
  const bool driven_a = amplitude_a_v > 0.0;
  const bool driven_b = amplitude_b_v > 0.0;
  if (!driven_a && !driven_b) return 1.0 / std::abs(network.divider(w));
  // One phase: commanded analytic signal V0 (sin - j cos) of its own phase angle, I = j w Q.
  auto phase_gain = [&](double amplitude_v, double sin_p, double cos_p, double charge_q1, double charge_q2) {
    const Phasor charge{charge_q1 * q1.re + charge_q2 * q2.re, charge_q1 * q1.im + charge_q2 * q2.im};
    const Phasor terminal = network.terminal_voltage_v(w, Phasor{amplitude_v * sin_p, -amplitude_v * cos_p},
                                                       Phasor{0.0, w} * charge);
    return std::abs(terminal) / amplitude_v;
  };
  auto gain_a = [&] { return phase_gain(amplitude_a_v, s, c, e.charge_a_q1, e.charge_a_q2); };
  auto gain_b = [&] {
    return phase_gain(amplitude_b_v, s * cos_phase + c * sin_phase, c * cos_phase - s * sin_phase, e.charge_b_q1,
                      e.charge_b_q2);
  };
  if (!driven_b) return gain_a();
  if (!driven_a) return gain_b();
  return 0.5 * (gain_a() + gain_b());
}

}  // namespace swum
