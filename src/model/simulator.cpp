#include "model/simulator.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "integrators/semi_implicit_euler.h"

namespace swum {

MotorSimulator::MotorSimulator(const MotorModel& model)
    : model_(model),
      system_(model.coefficients(), model.time_step_s()),
      state_(model.rest_state()),
      dt_(model.time_step_s()),
      position_limit_m_(model.parameters().numerics.divergence_limit_um * 1e-6),
      speed_limit_m_s_(model.parameters().numerics.divergence_speed_limit_m_s) {
  drive_.vpp = 0.0;
  set_drive(drive_);
}

void MotorSimulator::set_drive(const DriveInput& input) {
  const bool same_waveform = waveform_valid_ && input.frequency_hz == drive_.frequency_hz &&
                             input.phase_deg == drive_.phase_deg;
  if (same_waveform) {
    // Only amplitude and load changed: no trigonometric calls (set_drive may run every tick).
    waveform_.amplitude_v = model_.coefficients().drive_amplitude_per_volt * input.vpp;
  } else {
    waveform_ = make_drive_waveform(input, model_.coefficients().drive_amplitude_per_volt, dt_);
    waveform_valid_ = true;
  }
  apply_phase_gains();
  drive_ = input;
}

void MotorSimulator::apply_phase_gains() {
  // V_A = g_A V0 sin(theta), V_B = g_B V0 sin(theta + phase) (model_spec §4 with the phase
  // faults); a gain of 1 leaves V0 exactly.
  waveform_.amplitude_a_v = waveform_.amplitude_v * faults_.phase_a_gain;
  waveform_.amplitude_b_v = waveform_.amplitude_v * faults_.phase_b_gain;
}

void MotorSimulator::hold_jammed_mover() {
  if (!faults_.jammed) return;
  state_.mover_position_m = faults_.jam_position_m;
  state_.mover_velocity_m_s = 0.0;
}

void MotorSimulator::set_faults(const ModelFaults& faults) {
  const std::string problem = check(faults);
  if (!problem.empty()) throw std::invalid_argument("MotorSimulator::set_faults: " + problem);
  faults_ = faults;
  if (faults_.jammed && std::isnan(faults_.jam_position_m)) faults_.jam_position_m = state_.mover_position_m;
  hold_jammed_mover();
  apply_phase_gains();
  // F_P in F_N = max(0, F_P - k_e q1) and the constant back-end term gNP F_P (model_spec §4),
  // mu_s of the guide friction (eqs. 24-25).
  system_.set_preload_factor(model_.coefficients(), faults_.preload_factor);
  system_.set_guide_friction_factor(model_.coefficients(), faults_.guide_friction_factor);
}

void MotorSimulator::step() { advance(1); }

namespace {
// Values this small are physically zero; flushing them avoids subnormal arithmetic (x100 slower)
// when a mode decays at zero drive.
inline double flush_tiny(double x) { return std::abs(x) < 1e-200 ? 0.0 : x; }
}  // namespace

void MotorSimulator::advance(std::uint64_t steps) {
  system_.dispatch([&]<TangentialContact C, GuideFrictionModel G>() {
    faults_.jammed ? advance_specialised<C, G, false, true>(steps, nullptr)
                   : advance_specialised<C, G, false, false>(steps, nullptr);
  });
}

void MotorSimulator::advance(std::uint64_t steps, WindowStatistics& window) {
  system_.dispatch([&]<TangentialContact C, GuideFrictionModel G>() {
    faults_.jammed ? advance_specialised<C, G, true, true>(steps, &window)
                   : advance_specialised<C, G, true, false>(steps, &window);
  });
}

void MotorSimulator::advance(std::uint64_t steps, ElectricalSums& sums) {
  system_.dispatch([&]<TangentialContact C, GuideFrictionModel G>() {
    faults_.jammed ? advance_specialised<C, G, false, true, true>(steps, nullptr, &sums)
                   : advance_specialised<C, G, false, false, true>(steps, nullptr, &sums);
  });
}

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
  // (sin, cos) at t_n+1/2 = the mean of the phasors at t_n and t_n+1 / cos(w dt/2).
  [[maybe_unused]] const double half_step_secant =
      kElectrical ? 1.0 / (2.0 * std::cos(0.5 * waveform_.angular_frequency_rad_s * dt_)) : 0.0;
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
        const double s_mid = (s_start + s) * half_step_secant;
        const double c_mid = (c_start + c) * half_step_secant;
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
      for (auto& x : v) x = flush_tiny(x);
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

void MotorSimulator::update_effects(const MotorSplitSystem::Vector& q, const MotorSplitSystem::Vector& v,
                                    double sin_theta, double cos_theta, DriveWaveform& waveform) {
  const EffectCoefficients& e = model_.coefficients().effects;
  constexpr double kBlockSteps = 64.0;
  const double block_s = kBlockSteps * dt_;
  if (e.slow() && !slow_states_frozen_) {
    if (e.thermal) {
      // The block spans about one drive period (64 steps: 1.33 periods at 48 steps per 40 kHz
      // period), so an instantaneous C v^2 would be sampled at a few recurring phases: the
      // phase-independent cycle mean heats the stator.
      const double power_w = system_.mean_damping_power_w(q[0] - model_.constants().static_q1_m, q[1], v,
                                                          waveform.angular_frequency_rad_s);
      state_.stator_temperature_rise_k = thermal_step_k(e, state_.stator_temperature_rise_k, power_w, block_s);
    }
    if (e.wear) state_.sliding_distance_m += block_s * std::abs(v[2]);
    apply_slow_states();
  }
  if (e.droop) {
    const double w = waveform.angular_frequency_rad_s;
    const double inv_w = w > 0.0 ? 1.0 / w : 0.0;
    const Analytic z1{q[0] - model_.constants().static_q1_m, -v[0] * inv_w};
    const Analytic z2{q[1], -v[1] * inv_w};
    const double target = swum::droop_gain(e, w, sin_theta, cos_theta, waveform.cos_phase, waveform.sin_phase,
                                           waveform_.amplitude_a_v, waveform_.amplitude_b_v, z1, z2);
    // Half-way per block (~1 drive period): the modes respond over ~20 periods, so the
    // discrete feedback through the motional current stays smooth and stable.
    droop_gain_ += 0.5 * (target - droop_gain_);
    waveform.amplitude_a_v = waveform_.amplitude_a_v * droop_gain_;
    waveform.amplitude_b_v = waveform_.amplitude_b_v * droop_gain_;
  }
}

void MotorSimulator::apply_slow_states() {
  const MotorCoefficients& k = model_.coefficients();
  const EffectCoefficients& e = k.effects;
  if (e.thermal) {
    const ThermalFactors f = thermal_factors(e, ambient_offset_k_ + state_.stator_temperature_rise_k);
    system_.set_modal_factors(k, f.stiffness, f.damping);
  }
  if (e.wear) {
    system_.set_friction_coefficient(k.friction_coefficient * wear_friction_factor(e, state_.sliding_distance_m));
  }
}

void MotorSimulator::set_ambient_offset_k(double offset_k) {
  if (!std::isfinite(offset_k)) throw std::invalid_argument("MotorSimulator::set_ambient_offset_k: not finite");
  ambient_offset_k_ = offset_k;
  apply_slow_states();
}

void MotorSimulator::set_slow_states(double temperature_rise_k, double sliding_distance_m, bool frozen) {
  const EffectCoefficients& e = model_.coefficients().effects;
  state_.stator_temperature_rise_k = e.thermal ? temperature_rise_k : 0.0;
  state_.sliding_distance_m = e.wear ? sliding_distance_m : 0.0;
  slow_states_frozen_ = frozen;
  apply_slow_states();
}

void MotorSimulator::set_state(const MotorState& state) {
  state_ = state;
  apply_slow_states();
  system_.set_contact_deflection_m(state_.contact_deflection_m);
  state_.contact_deflection_m = system_.contact_deflection_m();
  const double r = std::hypot(state_.drive_sin, state_.drive_cos);
  if (r > 0.0 && std::isfinite(r)) {
    state_.drive_sin /= r;
    state_.drive_cos /= r;
  } else {
    state_.drive_sin = 0.0;
    state_.drive_cos = 1.0;
  }
  hold_jammed_mover();
}

void MotorSimulator::reset() {
  const MotorState rest = model_.rest_state(state_.time_s);
  const double s = state_.drive_sin;
  const double c = state_.drive_cos;
  const double temperature = state_.stator_temperature_rise_k;  // slow states persist
  const double distance = state_.sliding_distance_m;
  state_ = rest;
  state_.stator_temperature_rise_k = temperature;
  state_.sliding_distance_m = distance;
  system_.set_contact_deflection_m(0.0);
  state_.drive_sin = s;
  state_.drive_cos = c;
  hold_jammed_mover();
}

MotorOutputs MotorSimulator::outputs() const {
  MotorOutputs o;
  o.time_s = state_.time_s;
  o.tip_normal_um = 1e6 * MotorModel::tip_normal_m(state_);
  o.tip_tangential_um = 1e6 * model_.tip_tangential_m(state_);
  o.normal_force_n = system_.forces().normal_n;
  o.friction_force_n = system_.forces().friction_n;
  o.guide_force_n = system_.forces().guide_n;
  o.mover_position_m = state_.mover_position_m;
  o.mover_velocity_m_s = state_.mover_velocity_m_s;
  return o;
}

}  // namespace swum
