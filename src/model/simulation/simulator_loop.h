// The fixed-step hot loops of MotorSimulator (simulator.h), as templates for the translation
// units that instantiate them: simulator.cpp (plain and windowed steps) and
// simulator_electrical.cpp (steps with the electrical port). Private to the model library.
// advance_specialised is the semi-implicit Euler step of MotorSplitSystem for every contact law;
// advance_jenkins is the same step fused by hand for the calibrated contact (Jenkins element,
// implicit Coulomb guide), which every sweep, fit and the emulator run (issue 16).
// Why two units: with every variant in one unit GCC ran out of inlining budget and the plain
// loop, the emulator's and every sweep's, ran 45 % slower (docs/performance.md, issue 15).
#pragma once

#include <algorithm>
#include <cmath>

#include "integrators/semi_implicit_euler.h"
#include "model/machine/drive_recurrence.h"
#include "model/simulation/simulator.h"

namespace swum {

namespace simulator_detail {
// Values this small are physically zero; flushing them avoids subnormal arithmetic (x100 slower)
// when a mode decays at zero drive.
inline double flush_tiny(double x) { return std::abs(x) < 1e-200 ? 0.0 : x; }
// Note on bit-identity (PairedWindow, advance_jenkins against step() loops): the model library
// is built without FP contraction into fused multiply-adds (GCC, x86-64 baseline: no FMA);
// a build that contracts a * b + c in one translation unit and not in another breaks the
// bit-for-bit claims below, though not the results' accuracy.
// x clipped to [-limit, limit] (limit >= 0; NaN stays NaN), written as branches on purpose: the
// clips lie on the step's critical dependency chain (the deflection's and the mover's), a
// predicted branch costs no latency where min/max instructions cost 8 cycles, and the
// mispredictions (a few stick-slip events per drive period) cost less: 12 % faster per step
// (docs/performance.md).
inline double clamp_symmetric(double x, double limit) {
  if (__builtin_expect(x > limit, 0)) return limit;
  if (__builtin_expect(x < -limit, 0)) return -limit;
  return x;
}

// WindowStatistics::add's arithmetic on lane pairs (the tip extremes (u, w), the sums of F_T and
// F_N, the two damping powers): the same IEEE operations in the same order, so the same sums
// as add() (tested bit for bit), at ~16 operations per step instead of ~25.
struct PairedWindow {
  DoublePair damping, scale, low, high, force_sums;
  double energy_j, duration_s, contact_s, ft2_sum_n2_s, slip_energy_j, mover_energy_j, g_t;

  PairedWindow(const WindowStatistics& w, double g_tv, double g_t_force)
      : damping{w.c1_n_s_m, w.c2_n_s_m},
        scale{-1.0, g_tv},
        low{w.u_min_m, w.w_min_m},
        high{w.u_max_m, w.w_max_m},
        force_sums{w.ft_sum_n_s, w.fn_sum_n_s},
        energy_j(w.energy_j),
        duration_s(w.duration_s),
        contact_s(w.contact_s),
        ft2_sum_n2_s(w.ft2_sum_n2_s),
        slip_energy_j(w.slip_energy_j),
        mover_energy_j(w.mover_energy_j),
        g_t(g_t_force) {}

  // add(dt, -q1, g_tv q2, fn, ft, damping_power_w(v1, v2)) and add_interface(dt, ft, g_t v2, vm).
  void add(double dt, DoublePair q, DoublePair v, double vm, double fn, double ft) {
    const DoublePair p = (damping * v) * v;  // C1 v1 v1, C2 v2 v2
    energy_j += dt * (p[0] + p[1]);
    duration_s += dt;
    const DoublePair uw = q * scale;  // (-q1, g_tv q2)
    low = uw < low ? uw : low;        // std::min(low, uw)
    high = high < uw ? uw : high;     // std::max(high, uw)
    if (fn > 0.0) contact_s += dt;
    const DoublePair impulse = dt * DoublePair{ft, fn};
    force_sums += impulse;
    ft2_sum_n2_s += impulse[0] * ft;
    slip_energy_j += impulse[0] * (g_t * v[1] - vm);
    mover_energy_j += impulse[0] * vm;
  }

  void store(WindowStatistics& w) const {
    w.energy_j = energy_j;
    w.duration_s = duration_s;
    w.u_min_m = low[0];
    w.w_min_m = low[1];
    w.u_max_m = high[0];
    w.w_max_m = high[1];
    w.contact_s = contact_s;
    w.ft_sum_n_s = force_sums[0];
    w.fn_sum_n_s = force_sums[1];
    w.ft2_sum_n2_s = ft2_sum_n2_s;
    w.slip_energy_j = slip_energy_j;
    w.mover_energy_j = mover_energy_j;
  }
};
// The electrical port's sample of one step (both loops): v_n+1 is the velocity over the step
// (centred at t_n+1/2), so q, V, V' and the fit's basis are taken there too and the powers are
// second-order accurate (with q_n and V_n, or q_n+1 and V_n+1, the electrical power is off by
// ~O(w dt), 13 % at 48 steps per period). (s, c) at the midpoint = (phasor at t_n + phasor at
// t_n+1) x midpoint_scale.
inline void sample_electrical(const PairedForceCoefficients& m, double clamped_capacitance_f, const DriveWaveform& w,
                              double midpoint_scale, double s_start, double c_start, double s_end, double c_end,
                              DoublePair q_start, DoublePair q_end, DoublePair v, double weight_s,
                              ElectricalSums& sums) {
  const double s_mid = (s_start + s_end) * midpoint_scale;
  const double c_mid = (c_start + c_end) * midpoint_scale;
  const DriveVoltages u_mid = drive_voltages(w, s_mid, c_mid);
  const DriveVoltages du_mid = drive_voltage_rates(w, s_mid, c_mid);
  const PhaseCurrents i = phase_currents(m, clamped_capacitance_f, 0.5 * (q_start + q_end), v, u_mid.va_v, u_mid.vb_v,
                                         du_mid.va_v, du_mid.vb_v);
  sums.add(i, s_mid, c_mid, u_mid.va_v, u_mid.vb_v, weight_s);
}
}  // namespace simulator_detail

template <TangentialContact C, GuideFrictionModel G, bool kWindow, bool kJammed, bool kElectrical>
void MotorSimulator::advance_specialised(std::uint64_t steps, WindowStatistics* window, ElectricalSums* sums) {
  if constexpr (C == TangentialContact::jenkins && G == GuideFrictionModel::implicit_coulomb && !kJammed) {
    if (fused_step_) {
      advance_jenkins<kWindow, kElectrical>(steps, window, sums);
      return;
    }
  }
  drive_recurrence_state_ = RecurrenceState::unanchored;  // this loop rotates the phasor itself
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
  DriveWaveform waveform = amplified_waveform();
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
        simulator_detail::sample_electrical(system_.paired_coefficients(), clamped_capacitance_f, waveform,
                                            midpoint_scale, s_start, c_start, s, c, q_start, DoublePair{q[0], q[1]},
                                            DoublePair{v[0], v[1]}, kElectricalStride * dt, *sums);
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
      window->add_interface(dt, f.friction_n, model_.coefficients().g_t * v[1], v[2]);
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

// MotorSplitSystem's step (motor.h: explicit accelerations, implicit_velocity_correction with the
// Jenkins element and the implicit Coulomb guide, the return mapping) for the calibrated
// contact, fused into one loop over local copies of the state and the constants, in the same
// order of evaluation; what differs is arithmetic rearranged for a shorter dependency chain per
// step (products of step constants folded, the mover's update in displacement units, the
// position update from the modal force directly), so the results agree with
// advance_specialised's to rounding (tested), not bit for bit. The drive comes from
// DriveRecurrence. Why: the generic step spent ~100 floating-point operations and ~210
// instructions per step (voltages and their products, stores and reloads of the system's
// members); this one ~60 and ~140 (docs/performance.md, issue 16).
template <bool kWindow, bool kElectrical>
void MotorSimulator::advance_jenkins(std::uint64_t steps, WindowStatistics* window, ElectricalSums* sums) {
  const EffectCoefficients& effects = model_.coefficients().effects;
  DriveWaveform waveform = amplified_waveform();
  const double dt = dt_;
  const double inv_dt = 1.0 / dt;
  const double load = drive_.load_n;
  // Step constants (MotorSplitSystem::update_step), read again after the effects change them:
  // v+ = v + dt A (f + [gN F_N, -gT F_T] - C v) = damp v + dt A force, with gNP F_P in f's c0.
  DoublePair k3, damp, dt_a, dt_dt_a;
  double g_n = 0.0, kt = 0.0, g_t_kt = 0.0, dt_keep = 0.0, dt_push = 0.0, dt_dtm_kt = 0.0, dt_dmu = 0.0, dt_dmu_w = 0.0,
         slider = 0.0, dt_gtv = 0.0, preload = 0.0, ke = 0.0, m_over_dt = 0.0;
  const auto load_constants = [&] {
    const MotorCoefficients& k = system_.coefficients();
    const MotorSplitSystem::StepConstants sc = system_.step_constants();
    k3 = system_.paired_coefficients().k3;
    damp = DoublePair{1.0 - dt * sc.a1_per_kg * k.c1_n_s_m, 1.0 - dt * sc.a2_per_kg * k.c2_n_s_m};
    dt_a = DoublePair{dt * sc.a1_per_kg, dt * sc.a2_per_kg};
    dt_dt_a = dt * dt_a;
    g_n = k.g_n;
    kt = k.tangential_stiffness_n_m;
    g_t_kt = k.g_t * kt;
    // Mover in displacement units u = dt v: u_pred = dt keep v_m + dt (dt/m)(-load) +
    // dt (dt/m) F_T; the guide holds |u| <= dt cap, cap = dt mu_s (F_N + g m)/m.
    dt_keep = dt * (1.0 - sc.dt_over_m * k.mover_damping_n_s_m);
    dt_push = -dt * sc.dt_over_m * load;
    dt_dtm_kt = dt * sc.dt_over_m * kt;
    dt_dmu = dt * sc.dt_mu_s_over_m;
    dt_dmu_w = dt_dmu * k.guide.weight_n;
    slider = k.slider_limit_per_normal_force_m_n;
    dt_gtv = dt * k.g_tv;
    preload = k.preload_n;
    ke = k.contact_stiffness_n_m;
    m_over_dt = sc.m_over_dt;
  };
  load_constants();
  // gNP F_P (eq. 14's constant back-end term) in the cubic's constant: it is a force on L1 like c0.
  DoublePair constant_force{system_.coefficients().preload_constant_force_n, 0.0};
  std::uint64_t housekeeping = housekeeping_steps_;
  if (drive_recurrence_state_ != RecurrenceState::current) {
    // A new phasor or frequency anchors the recurrence here; new amplitudes or a new stiffness
    // are replayed from the last anchor (the last 64-step boundary), so that the values do not
    // depend on when the change was made: a simulator that always had them has the same bits.
    if (drive_recurrence_state_ == RecurrenceState::unanchored) {
      recurrence_anchor_ = {state_.drive_sin, state_.drive_cos, housekeeping};
    }
    drive_recurrence_.seed(system_.paired_coefficients(), constant_force, waveform, recurrence_anchor_.sin_theta,
                           recurrence_anchor_.cos_theta);
    for (std::uint64_t n = recurrence_anchor_.step; n < housekeeping; ++n) drive_recurrence_.next();
    drive_recurrence_state_ = RecurrenceState::current;
  }
  DriveRecurrence drive = drive_recurrence_;
  DoublePair q{state_.q1_m, state_.q2_m};
  DoublePair v{state_.q1_dot_m_s, state_.q2_dot_m_s};
  double xm = state_.mover_position_m;
  double vm = state_.mover_velocity_m_s;
  double delta = system_.contact_deflection_m();
  double fn = normal_force_n(preload, ke, q[0]);  // eq. 16 at q1_n (the step's F_N)
  // Outside the cone only after set_state(), a lower preload (set_faults) or a lower mu_c
  // (set_slow_states, set_ambient_offset_k with wear): projected onto it, as the generic step
  // does at every step (MotorSplitSystem::implicit_velocity_correction) and the lanes do.
  delta = simulator_detail::clamp_symmetric(delta, slider * fn);
  bool mover_finite = xm - xm == 0.0;  // x - x is NaN for NaN and Inf
  InterfaceForces last = system_.forces();
  double u_held = 0.0;
  double t = state_.time_s;
  const double position_limit_sq = position_limit_m_ * position_limit_m_;
  const double speed_limit_sq = speed_limit_m_s_ * speed_limit_m_s_;
  [[maybe_unused]] const double clamped_capacitance_f = model_.coefficients().clamped_capacitance_f;
  [[maybe_unused]] const double midpoint_scale = midpoint_scale_;
  // The window's sums in a local copy: written through the pointer, every field was a load and
  // a store per step (the compiler cannot keep what may alias in registers). Same sums.
  [[maybe_unused]] simulator_detail::PairedWindow sums_window{kWindow ? *window : WindowStatistics{},
                                                              system_.coefficients().g_tv, system_.coefficients().g_t};
  for (std::uint64_t k = 0; k < steps; ++k) {
    const ModalCubic cubic = drive.cubic();
    [[maybe_unused]] const double s_start = drive.sin_theta(), c_start = drive.cos_theta();
    drive.next();
    [[maybe_unused]] const DoublePair q_start = q;
    [[maybe_unused]] const double fn_start = fn;
    const DoublePair f = modal_forces_n(cubic, k3, q);  // eqs. 14-15
    // The Jenkins force k_t delta: delta lies inside the cone mu_c F_N(t_n) (the last return
    // mapping used the same F_N; after set_state(), a lower preload or wear it was projected).
    const double ft = kt * delta;
    // The interface forces on the modes (gN F_N on L1, -gT F_T on B2) join the modal forces before
    // the step's products (one addition on the way from F_N to the next q).
    const DoublePair force = f + DoublePair{g_n * fn, -g_t_kt * delta};
    const DoublePair base = damp * v;
    v = base + dt_a * force;
    q = (q + dt * base) + dt_dt_a * force;  // q + dt v+, with the forces one product nearer
    // Guide (coulomb_guide_velocity_m_s in displacement units): stuck (du = 0 exactly) while the
    // guide friction can stop the mover.
    const double u_pred = dt_keep * vm + dt_push + dt_dtm_kt * delta;
    u_held = simulator_detail::clamp_symmetric(u_pred, dt_dmu * fn + dt_dmu_w);
    const double um = u_pred - u_held;
    vm = um * inv_dt;
    xm += um;
    // Return mapping with F_N at the end of the step, which is also the next step's F_N.
    fn = normal_force_n(preload, ke, q[0]);
    delta = simulator_detail::clamp_symmetric((delta - um) + dt_gtv * v[1], slider * fn);
    if constexpr (kElectrical) {
      // Every kElectricalStride-th step, at the step's midpoint (see advance_specialised).
      if ((housekeeping & (kElectricalStride - 1)) == kElectricalStride - 1) {
        simulator_detail::sample_electrical(system_.paired_coefficients(), clamped_capacitance_f, waveform,
                                            midpoint_scale, s_start, c_start, drive.sin_theta(), drive.cos_theta(),
                                            q_start, q, v, kElectricalStride * dt, *sums);
      }
    }
    t += dt;
    if ((++housekeeping & 63U) == 0U) {
      double s = drive.sin_theta();
      double c = drive.cos_theta();
      renormalise_phasor(s, c);
      v[0] = simulator_detail::flush_tiny(v[0]);
      v[1] = simulator_detail::flush_tiny(v[1]);
      vm = simulator_detail::flush_tiny(vm);
      // A decaying B2 mode at rest reaches ~1e-160 m, whose square (the cubic's q^2) is
      // subnormal: x100 slower arithmetic on every step. Below 1e-150 m it is zero.
      q[1] = std::abs(q[1]) < 1e-150 ? 0.0 : q[1];
      if (effects.any()) [[unlikely]] {
        update_effects(MotorSplitSystem::Vector{q[0], q[1], xm}, MotorSplitSystem::Vector{v[0], v[1], vm}, s, c,
                       waveform);
        load_constants();
        delta = simulator_detail::clamp_symmetric(delta, slider * fn);  // a lower mu_c (wear)
      }
      drive.seed(system_.paired_coefficients(), constant_force, waveform, s, c);
      recurrence_anchor_ = {s, c, housekeeping};
    }
    // Runaway limits on q1, q2 (q1^2 + q2^2 < limit^2, as the generic step) and v_m. A NaN or
    // Inf in v reaches q in the same step, one in delta reaches v_m, and x_m changes by dt v_m
    // only: a non-finite x_m can only come from set_state() (mover_finite, checked once).
    const DoublePair q_sq = q * q;
    // One branch for the three conditions (each a branch of its own made the step slower).
    const bool sane = (q_sq[0] + q_sq[1] < position_limit_sq) & (vm * vm < speed_limit_sq) & mover_finite;
    if (!sane) [[unlikely]] {
      const MotorState rest = model_.rest_state(t);
      q = DoublePair{rest.q1_m, rest.q2_m};
      v = DoublePair{rest.q1_dot_m_s, rest.q2_dot_m_s};
      xm = rest.mover_position_m;
      vm = rest.mover_velocity_m_s;
      delta = 0.0;
      fn = normal_force_n(preload, ke, q[0]);
      mover_finite = true;
      diverged_ = true;
      ++divergence_count_;
    }
    if constexpr (kWindow) {
      // What a caller of step() reads after it: the end state and this step's forces.
      sums_window.add(dt, q, v, vm, fn_start, ft);
    }
    last.normal_n = fn_start;
    last.friction_n = ft;
  }
  if constexpr (kWindow) sums_window.store(*window);
  if (steps > 0) {
    // F_f = (v_m+ - v_pred) m/dt = -held m/dt (motor.h).
    last.guide_n = -u_held * inv_dt * m_over_dt;
    system_.set_forces(last);
  }
  drive_recurrence_ = drive;
  drive_recurrence_state_ = RecurrenceState::current;  // update_effects' changes were reseeded
  if (steps == 0) return;                              // advance(0) changes nothing (not even the projection above)
  housekeeping_steps_ = housekeeping;
  state_.q1_m = q[0];
  state_.q2_m = q[1];
  state_.mover_position_m = xm;
  state_.q1_dot_m_s = v[0];
  state_.q2_dot_m_s = v[1];
  state_.mover_velocity_m_s = vm;
  system_.set_contact_deflection_m(delta);
  state_.contact_deflection_m = delta;
  state_.drive_sin = drive.sin_theta();
  state_.drive_cos = drive.cos_theta();
  state_.time_s = t;
}

}  // namespace swum
