// The fixed-step hot loop of MotorSimulator (simulator.h), as a template for the translation
// units that instantiate it: simulator.cpp (plain and windowed steps) and
// simulator_electrical.cpp (steps with the electrical port). Private to the model library.
// Why two units: with every variant in one unit GCC ran out of inlining budget and the plain
// loop, the emulator's and every sweep's, ran 45 % slower (docs/performance.md, issue 15).
#pragma once

#include <cmath>

#include "integrators/semi_implicit_euler.h"
#include "model/simulator.h"

namespace swum {

namespace simulator_detail {
// Values this small are physically zero; flushing them avoids subnormal arithmetic (x100 slower)
// when a mode decays at zero drive.
inline double flush_tiny(double x) { return std::abs(x) < 1e-200 ? 0.0 : x; }
}  // namespace simulator_detail

template <TangentialContact C, GuideFrictionModel G, bool kWindow, bool kJammed, bool kElectrical>
void MotorSimulator::advance_specialised(std::uint64_t steps, WindowStatistics* window, ElectricalSums* sums) {
  SpecialisedMotorSystem<C, G, kJammed> system{system_};
  MotorSplitSystem::Vector q{state_.q1_m, state_.q2_m, state_.mover_position_m};
  MotorSplitSystem::Vector v{state_.q1_dot_m_s, state_.q2_dot_m_s, state_.mover_velocity_m_s};
  [[maybe_unused]] const double jam_position_m = faults_.jam_position_m;
  if constexpr (kJammed) {
    // The held system keeps v_m = 0, so x_m stays at the jam position step after step.
    q[2] = jam_position_m;
    v[2] = 0.0;
  }
  double s = state_.drive_sin;
  double c = state_.drive_cos;
  double t = state_.time_s;
  const double load = drive_.load_n;
  const EffectCoefficients& effects = model_.coefficients().effects;
  DriveWaveform waveform = waveform_;
  waveform.amplitude_a_v *= droop_gain_;
  waveform.amplitude_b_v *= droop_gain_;
  const double dt = dt_;
  const double position_limit_sq = position_limit_m_ * position_limit_m_;
  const double speed_limit_sq = speed_limit_m_s_ * speed_limit_m_s_;
  [[maybe_unused]] const double g_tv = model_.coefficients().g_tv;  // window statistics only
  [[maybe_unused]] const double clamped_capacitance_f = model_.coefficients().clamped_capacitance_f;
  [[maybe_unused]] const double midpoint_scale = midpoint_scale_;
  std::uint64_t housekeeping = housekeeping_steps_;
  for (std::uint64_t k = 0; k < steps; ++k) {
    const DriveVoltages u = drive_voltages(waveform, s, c);
    system_.set_inputs(u, load);
    [[maybe_unused]] const DoublePair q_start{q[0], q[1]};
    semi_implicit_euler_step(system, t, dt, q, v);
    [[maybe_unused]] const double s_start = s, c_start = c;
    rotate_phasor(waveform, s, c);
    if constexpr (kElectrical) {
      // Every kElectricalStride-th step (by the global step count, so chunking does not matter):
      // 12 samples per 40 kHz period fit the fundamental and average V I exactly up to the 5th
      // harmonic, at a quarter of the cost (15 ns per sampled step; docs/performance.md).
      if ((housekeeping & (kElectricalStride - 1)) == kElectricalStride - 1) {
        // v_n+1 is the velocity over the step (centred at t_n+1/2): q, V, V' and the fit's basis
        // are taken there too, so the powers are second-order accurate (with q_n and V_n, or
        // q_n+1 and V_n+1, the electrical power is off by ~O(w dt), 13 % at 48 steps per period).
        const double s_mid = (s_start + s) * midpoint_scale;
        const double c_mid = (c_start + c) * midpoint_scale;
        const DriveVoltages u_mid = drive_voltages(waveform, s_mid, c_mid);
        const double w = waveform.angular_frequency_rad_s;
        const double dva = waveform.amplitude_a_v * w * c_mid;
        const double dvb = waveform.amplitude_b_v * w * (c_mid * waveform.cos_phase - s_mid * waveform.sin_phase);
        const DoublePair q_mid = 0.5 * (q_start + DoublePair{q[0], q[1]});
        const PhaseCurrents i = phase_currents(system_.paired_coefficients(), clamped_capacitance_f, q_mid,
                                               DoublePair{v[0], v[1]}, u_mid.va_v, u_mid.vb_v, dva, dvb);
        sums->add(i, s_mid, c_mid, u_mid.va_v, u_mid.vb_v, kElectricalStride * dt);
      }
    }
    t += dt;
    if ((++housekeeping & 63U) == 0U) {
      renormalise_phasor(s, c);
      for (auto& x : v) x = simulator_detail::flush_tiny(x);
      if (effects.any()) [[unlikely]]
        update_effects(q, v, s, c, waveform);
    }
    // Runaway limits on q1, q2, v_m; NaN fails every comparison and a NaN/Inf anywhere makes
    // the sum's difference with itself NaN.
    const double sum = v[0] + v[1] + q[2];
    const bool sane = q[0] * q[0] + q[1] * q[1] < position_limit_sq && v[2] * v[2] < speed_limit_sq && sum - sum == 0.0;
    if (!sane) [[unlikely]] {
      const MotorState rest = model_.rest_state(t);
      q = {rest.q1_m, rest.q2_m, rest.mover_position_m};
      v = {rest.q1_dot_m_s, rest.q2_dot_m_s, rest.mover_velocity_m_s};
      if constexpr (kJammed) {
        q[2] = jam_position_m;
        v[2] = 0.0;
      }
      system_.set_contact_deflection_m(0.0);
      diverged_ = true;
      ++divergence_count_;
    }
    if constexpr (kWindow) {
      // What a caller of step() reads after it: the end state and this step's forces.
      const InterfaceForces& f = system_.forces();
      window->add(dt, -q[0], g_tv * q[1], f.normal_n, f.friction_n, window->damping_power_w(v[0], v[1]));
    }
  }
  housekeeping_steps_ = housekeeping;
  state_.q1_m = q[0];
  state_.q2_m = q[1];
  state_.mover_position_m = q[2];
  state_.q1_dot_m_s = v[0];
  state_.q2_dot_m_s = v[1];
  state_.mover_velocity_m_s = v[2];
  state_.contact_deflection_m = system_.contact_deflection_m();
  state_.drive_sin = s;
  state_.drive_cos = c;
  state_.time_s = t;
}

}  // namespace swum
