// The drive as the hot loop sees it: the phasor (sin theta, cos theta) and the coefficients of
// the stator's modal cubic (stator.h, eqs. 14-15), stepped along a sinusoidal drive without
// voltages, products of voltages or trigonometry.
//
// Why: each coefficient of f = c0 + c1 q + c2 q^2 - k3 q^3 under V_A = A sin(theta),
// V_B = B sin(theta + phase) is a constant plus harmonic 1 (the terms linear in V) and harmonic
// 2 (the quadratic ones: V^2 = A^2/2 - A^2/2 cos 2 theta) of theta, and a harmonic h sampled every
// dt obeys x_n+1 = 2 cos(h w dt) x_n - x_n-1 exactly. Two operations per harmonic and step
// instead of the voltages and their products (~35 operations of the ~100 of a step;
// docs/performance.md, issue 16). Rounding makes the recurrence drift by ~n eps / sin(w dt)
// after n steps: the simulator reseeds it from the phasor every housekeeping block (64 steps).
#pragma once

#include "model/machine/drive.h"
#include "model/machine/stator.h"

namespace swum {

// f = c0 + c1 q + c2 q^2 - k3 q^3 of both modes (lane 0 = L1, lane 1 = B2).
struct ModalCubic {
  DoublePair c0, c1, c2;
};

[[nodiscard]] inline DoublePair modal_forces_n(const ModalCubic& c, DoublePair k3, DoublePair q) {
  // Estrin's form: the state-dependent chain is q^2 and one product shorter than Horner's.
  return (c.c0 + c.c1 * q) + (q * q) * (c.c2 - k3 * q);
}

class DriveRecurrence {
 public:
  // Values at the phasor (sin_theta, cos_theta) of the current step; the previous step's by
  // rotating back by w dt. constant_force_n: a force on the modes that does not depend on q or V
  // (the motor's constant preload term), added to c0.
  void seed(const PairedForceCoefficients& m, DoublePair constant_force_n, const DriveWaveform& w, double sin_theta,
            double cos_theta) {
    const DriveVoltages half_squares = half_mean_squares(w);
    const double ha = half_squares.va_v;
    const double hb = half_squares.vb_v;
    const DoublePair half_a2 = {ha, ha};
    const DoublePair half_b2 = {hb, hb};
    dc0_ = m.sq0_a * half_a2 + m.sq0_b * half_b2 + constant_force_n;
    dc1_ = m.sq1_a * half_a2 + m.sq1_b * half_b2 - m.k;
    dc2_ = -m.k2;
    harmonics_at(m, w, sin_theta, cos_theta, slots_[now_]);
    const double s_before = sin_theta * w.rotation_cos - cos_theta * w.rotation_sin;
    const double c_before = cos_theta * w.rotation_cos + sin_theta * w.rotation_sin;
    harmonics_at(m, w, s_before, c_before, slots_[now_ ^ 1U]);
    const double k1 = 2.0 * w.rotation_cos;                                 // 2 cos(w dt)
    const double k2 = 2.0 * (2.0 * w.rotation_cos * w.rotation_cos - 1.0);  // 2 cos(2 w dt)
    k1_ = DoublePair{k1, k1};
    k2_ = DoublePair{k2, k2};
  }

  [[nodiscard]] ModalCubic cubic() const {
    const Harmonics& h = slots_[now_];
    return {dc0_ + h.h1_0 + h.h2_0, dc1_ + h.h1_1 + h.h2_1, dc2_ + h.h1_2};
  }
  [[nodiscard]] double sin_theta() const { return slots_[now_].phasor[0]; }
  [[nodiscard]] double cos_theta() const { return slots_[now_].phasor[1]; }

  // One step: theta += w dt. x_n+1 overwrites x_n-1 in place and the two slots swap roles: no
  // copies (the state is twelve register pairs, more than the registers there are).
  void next() {
    const Harmonics& a = slots_[now_];
    Harmonics& b = slots_[now_ ^ 1U];
    b.phasor = k1_ * a.phasor - b.phasor;
    b.h1_0 = k1_ * a.h1_0 - b.h1_0;
    b.h2_0 = k2_ * a.h2_0 - b.h2_0;
    b.h1_1 = k1_ * a.h1_1 - b.h1_1;
    b.h2_1 = k2_ * a.h2_1 - b.h2_1;
    b.h1_2 = k1_ * a.h1_2 - b.h1_2;
    now_ ^= 1U;
  }

 private:
  struct Harmonics {
    DoublePair phasor;                        // (sin theta, cos theta)
    DoublePair h1_0, h2_0, h1_1, h2_1, h1_2;  // harmonic h of coefficient c_k: hh_k
  };
  static void harmonics_at(const PairedForceCoefficients& m, const DriveWaveform& w, double s, double c, Harmonics& h) {
    const DriveVoltages u = drive_voltages(w, s, c);
    const DriveVoltages half_squares = half_mean_squares(w);
    const double qa = u.va_v * u.va_v - half_squares.va_v;
    const double qb = u.vb_v * u.vb_v - half_squares.vb_v;
    const DoublePair a = {u.va_v, u.va_v}, b = {u.vb_v, u.vb_v}, a2 = {qa, qa}, b2 = {qb, qb};
    h.phasor = DoublePair{s, c};
    h.h1_0 = m.lin0_a * a + m.lin0_b * b;
    h.h2_0 = m.sq0_a * a2 + m.sq0_b * b2;
    h.h1_1 = m.lin1_a * a + m.lin1_b * b;
    h.h2_1 = m.sq1_a * a2 + m.sq1_b * b2;
    h.h1_2 = m.lin2_a * a + m.lin2_b * b;
  }

  DoublePair dc0_{}, dc1_{}, dc2_{};
  Harmonics slots_[2]{};
  unsigned now_ = 0;  // slots_[now_] holds x_n, the other x_n-1
  DoublePair k1_{}, k2_{};
};

}  // namespace swum
