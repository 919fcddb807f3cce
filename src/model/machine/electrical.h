// The electrical port of the two phases (docs/model.md "Electrical port"): what a two-phase
// amplifier measures at its outputs. The charge comes from the same electromechanical
// co-energy as the modal forces of eqs. 14-15, so the current includes the non-linear coupling
// terms and the electrical power equals the mechanical work of the electric forces:
//   W(q, V) = sum over modes i and phases X of
//             lin0 V q + sq0 V^2 q + lin1 V q^2/2 + sq1 V^2 q^2/2 + lin2 V q^3/3
//   f_i = dW/dq_i (the V-dependent part of eqs. 14-15),  Q_X = C0 V_X + dW/dV_X,
//   I_X = dQ_X/dt = C0 V_X' + sum_i (df_i/dV_X) q_i' + (d^2W/dV_X^2) V_X'
// (Maxwell reciprocity: dQ_X/dq_i = df_i/dV_X). Coefficients: stator.h (lin0 = a0, b0;
// sq0 = e311 a1; lin1 = e311 a2; sq1 = e3111 a3; lin2 = e3111 a4).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "model/machine/stator.h"

namespace swum {

// Instantaneous phase currents (A). motional = total - C0 V' (what a board with a parallel
// inductor or a bridge at the drive frequency sees: the clamped capacitance compensated).
struct PhaseCurrents {
  double a_a = 0.0;
  double b_a = 0.0;
  double motional_a_a = 0.0;
  double motional_b_a = 0.0;
};

// q, v: modal coordinates (lane 0 = L1, lane 1 = B2), va, vb: phase voltages, dva, dvb their
// time derivatives. ~30 flops.
[[nodiscard]] inline PhaseCurrents phase_currents(const PairedForceCoefficients& m, double clamped_capacitance_f,
                                                  DoublePair q, DoublePair v, double va, double vb, double dva,
                                                  double dvb) {
  const DoublePair a = {va, va};
  const DoublePair b = {vb, vb};
  // df_i/dV_X (lane i) and d^2W/dV_X^2 (lane i's share).
  const DoublePair dfa = m.lin0_a + 2.0 * m.sq0_a * a + q * (m.lin1_a + 2.0 * m.sq1_a * a + m.lin2_a * q);
  const DoublePair dfb = m.lin0_b + 2.0 * m.sq0_b * b + q * (m.lin1_b + 2.0 * m.sq1_b * b + m.lin2_b * q);
  const DoublePair capa = q * (2.0 * m.sq0_a + m.sq1_a * q);
  const DoublePair capb = q * (2.0 * m.sq0_b + m.sq1_b * q);
  const DoublePair ia = dfa * v + capa * dva;
  const DoublePair ib = dfb * v + capb * dvb;
  PhaseCurrents out;
  out.motional_a_a = ia[0] + ia[1];
  out.motional_b_a = ib[0] + ib[1];
  out.a_a = out.motional_a_a + clamped_capacitance_f * dva;
  out.b_a = out.motional_b_a + clamped_capacitance_f * dvb;
  return out;
}

// Sums over a window of steps for a least-squares fit of each current's drive-frequency
// component, I ~ x sin(theta) + y cos(theta) (theta: the drive phase, V_A = V_A0 sin theta),
// and for the real power. Exact for a sinusoid over any window, not only whole periods.
struct ElectricalSums {
  double samples = 0.0;
  double duration_s = 0.0;
  double ss = 0.0, cc = 0.0, sc = 0.0;                    // sum sin^2, cos^2, sin cos
  double a_s = 0.0, a_c = 0.0, b_s = 0.0, b_c = 0.0;      // sum I sin, I cos (terminal currents)
  double ma_s = 0.0, ma_c = 0.0, mb_s = 0.0, mb_c = 0.0;  // the same for the motional currents
  // sum V I_motional: the C0 current is reactive (zero mean over whole periods) and is left out,
  // so that a window that is not a whole number of periods shows no ripple from it.
  double power_a = 0.0, power_b = 0.0;
  // True RMS and peak of the terminal currents: sum I^2 and max |I| over the samples.
  double a_sq = 0.0, b_sq = 0.0;
  double a_peak = 0.0, b_peak = 0.0;
  // The phase voltages applied (after droop): sum V sin, V cos for their drive-frequency
  // amplitude, and sum V^2 for their RMS.
  double va_s = 0.0, va_c = 0.0, vb_s = 0.0, vb_c = 0.0;
  double va_sq = 0.0, vb_sq = 0.0;

  void add(const PhaseCurrents& i, double sin_theta, double cos_theta, double va, double vb, double dt) {
    samples += 1.0;
    duration_s += dt;
    ss += sin_theta * sin_theta;
    cc += cos_theta * cos_theta;
    sc += sin_theta * cos_theta;
    a_s += i.a_a * sin_theta;
    a_c += i.a_a * cos_theta;
    b_s += i.b_a * sin_theta;
    b_c += i.b_a * cos_theta;
    ma_s += i.motional_a_a * sin_theta;
    ma_c += i.motional_a_a * cos_theta;
    mb_s += i.motional_b_a * sin_theta;
    mb_c += i.motional_b_a * cos_theta;
    power_a += va * i.motional_a_a;
    power_b += vb * i.motional_b_a;
    a_sq += i.a_a * i.a_a;
    b_sq += i.b_a * i.b_a;
    a_peak = std::max(a_peak, std::abs(i.a_a));
    b_peak = std::max(b_peak, std::abs(i.b_a));
    va_s += va * sin_theta;
    va_c += va * cos_theta;
    vb_s += vb * sin_theta;
    vb_c += vb * cos_theta;
    va_sq += va * va;
    vb_sq += vb * vb;
  }
  ElectricalSums& operator+=(const ElectricalSums& o);
};

// What the amplifier reports per phase: the drive-frequency component of the current (peak A),
// its phase relative to that phase's voltage (deg in (-180, 180], + = current leads), the same
// for the motional current, and the real power (W); what a board designer sizes with: the true
// RMS and the largest sampled |I| of the terminal current (A), the drive-frequency amplitude of
// the voltage applied (V; below the command with amplifier droop), the apparent power
// V_rms I_rms (VA, true RMS of both) and the power factor P/S. valid = false when the window
// holds less than a quarter period (the fit is then undetermined): every value is 0.
struct ElectricalReadings {
  bool valid = false;
  double current_a_a = 0.0, current_b_a = 0.0;
  double phase_a_deg = 0.0, phase_b_deg = 0.0;
  double motional_current_a_a = 0.0, motional_current_b_a = 0.0;
  double motional_phase_a_deg = 0.0, motional_phase_b_deg = 0.0;
  double power_a_w = 0.0, power_b_w = 0.0;
  double rms_current_a_a = 0.0, rms_current_b_a = 0.0;
  double peak_current_a_a = 0.0, peak_current_b_a = 0.0;
  double voltage_a_v = 0.0, voltage_b_v = 0.0;
  double apparent_power_a_va = 0.0, apparent_power_b_va = 0.0;
  double power_factor_a = 0.0, power_factor_b = 0.0;
  double duration_s = 0.0;
};

// An angle in degrees wrapped to (-180, 180].
[[nodiscard]] inline double wrap_phase_deg(double deg) {
  double d = std::remainder(deg, 360.0);
  if (d <= -180.0) d += 360.0;
  return d;
}

// phase_deg: the drive's phase difference (V_B ahead of V_A), to refer phase B's currents to V_B.
[[nodiscard]] ElectricalReadings electrical_readings(const ElectricalSums& sums, double phase_deg);

}  // namespace swum
