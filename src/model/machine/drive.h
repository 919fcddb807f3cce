// Two-phase drive V_A = V0 sin(theta), V_B = V0 sin(theta + phase) (model_spec §4; with the
// default phase +90 deg V_B = V0 cos(theta)). The fixed-step simulator advances
// (sin theta, cos theta) by a rotation exp(i w dt) per step instead of calling sin().
#pragma once

#include <cmath>
#include <numbers>

#include "model/motor_model.h"

namespace swum {

struct DriveVoltages {
  double va_v = 0.0;
  double vb_v = 0.0;
};

struct DriveWaveform {
  // V_A and V_B amplitudes applied: V0, times the phase-fault gain and the droop in
  // MotorSimulator (model_faults.h). First in the struct: the simulator scales the pair in its
  // local copy, and a 16-byte load of it then matches the copy's 16-byte stores (store
  // forwarding; at offset 8 it straddles two and stalls each advance() call by ~20 ns).
  double amplitude_a_v = 0.0;
  double amplitude_b_v = 0.0;
  double amplitude_v = 0.0;  // V0 (commanded, both phases)
  double cos_phase = 0.0;    // cos(phase)
  double sin_phase = 1.0;    // sin(phase)
  double angular_frequency_rad_s = 0.0;
  double rotation_cos = 1.0;  // cos(w dt)
  double rotation_sin = 0.0;  // sin(w dt)
  // The amplifier's output network shifts each phase (MotorSimulator, output_network.h): V_A =
  // amplitude_a sin(theta) + quadrature_a cos(theta), V_B = amplitude_b sin(theta + phase) +
  // quadrature_b cos(theta + phase). Without a network `shifted` is false and the quadratures
  // are never read (the voltages are the same bits as before the network existed).
  bool shifted = false;
  double quadrature_a_v = 0.0;
  double quadrature_b_v = 0.0;
};

[[nodiscard]] inline DriveWaveform make_drive_waveform(const DriveInput& input, double amplitude_per_volt,
                                                       double time_step_s) {
  DriveWaveform w;
  w.amplitude_v = amplitude_per_volt * input.amplitude_v;
  w.amplitude_a_v = w.amplitude_v;
  w.amplitude_b_v = w.amplitude_v;
  const double phase = input.phase_deg * std::numbers::pi / 180.0;
  w.cos_phase = std::cos(phase);
  w.sin_phase = std::sin(phase);
  w.angular_frequency_rad_s = 2.0 * std::numbers::pi * input.frequency_hz;
  w.rotation_cos = std::cos(w.angular_frequency_rad_s * time_step_s);
  w.rotation_sin = std::sin(w.angular_frequency_rad_s * time_step_s);
  return w;
}

[[nodiscard]] inline DriveVoltages drive_voltages(const DriveWaveform& w, double sin_theta, double cos_theta) {
  DriveVoltages u{w.amplitude_a_v * sin_theta, w.amplitude_b_v * (sin_theta * w.cos_phase + cos_theta * w.sin_phase)};
  if (w.shifted) [[unlikely]] {
    u.va_v += w.quadrature_a_v * cos_theta;
    u.vb_v += w.quadrature_b_v * (cos_theta * w.cos_phase - sin_theta * w.sin_phase);
  }
  return u;
}

// dV_A/dt, dV_B/dt at the phasor (sin theta, cos theta).
[[nodiscard]] inline DriveVoltages drive_voltage_rates(const DriveWaveform& w, double sin_theta, double cos_theta) {
  const double omega = w.angular_frequency_rad_s;
  DriveVoltages u{w.amplitude_a_v * omega * cos_theta,
                  w.amplitude_b_v * omega * (cos_theta * w.cos_phase - sin_theta * w.sin_phase)};
  if (w.shifted) [[unlikely]] {
    u.va_v -= w.quadrature_a_v * omega * sin_theta;
    u.vb_v -= w.quadrature_b_v * omega * (sin_theta * w.cos_phase + cos_theta * w.sin_phase);
  }
  return u;
}

// The mean of V_A^2 and V_B^2 over a period, over 2: (amplitude^2 + quadrature^2)/2.
[[nodiscard]] inline DriveVoltages half_mean_squares(const DriveWaveform& w) {
  DriveVoltages h{0.5 * w.amplitude_a_v * w.amplitude_a_v, 0.5 * w.amplitude_b_v * w.amplitude_b_v};
  if (w.shifted) [[unlikely]] {
    h.va_v += 0.5 * w.quadrature_a_v * w.quadrature_a_v;
    h.vb_v += 0.5 * w.quadrature_b_v * w.quadrature_b_v;
  }
  return h;
}

// theta += w dt. The modulus drifts by ~1e-16 per step; call renormalise_phasor() every few
// dozen steps.
inline void rotate_phasor(const DriveWaveform& w, double& sin_theta, double& cos_theta) {
  const double s = sin_theta * w.rotation_cos + cos_theta * w.rotation_sin;
  const double c = cos_theta * w.rotation_cos - sin_theta * w.rotation_sin;
  sin_theta = s;
  cos_theta = c;
}

// First-order renormalisation to |phasor| = 1 (exact to rounding for a near-unit phasor).
inline void renormalise_phasor(double& sin_theta, double& cos_theta) {
  const double k = 1.5 - 0.5 * (sin_theta * sin_theta + cos_theta * cos_theta);
  sin_theta *= k;
  cos_theta *= k;
}

}  // namespace swum
