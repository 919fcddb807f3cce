#include "model/simulation/simulator.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "model/simulation/simulator_loop.h"

namespace swum {

MotorSimulator::MotorSimulator(const MotorModel& model)
    : model_(model),
      system_(model.coefficients(), model.time_step_s()),
      state_(model.rest_state()),
      dt_(model.time_step_s()),
      position_limit_m_(model.parameters().numerics.divergence_limit_um * 1e-6),
      speed_limit_m_s_(model.parameters().numerics.divergence_speed_limit_m_s),
      fused_step_(model.parameters().numerics.step_kernel == StepKernel::fused) {
  drive_.amplitude_v = 0.0;
  set_drive(drive_);
}

void MotorSimulator::set_drive(const DriveInput& input) {
  const bool same_waveform = waveform_valid_ && input.frequency_hz == drive_.frequency_hz &&
                             input.phase_deg == drive_.phase_deg;
  if (same_waveform) {
    // Only amplitude and load changed: no trigonometric calls (set_drive may run every tick).
    waveform_.amplitude_v = model_.coefficients().drive_amplitude_per_volt * input.amplitude_v;
  } else {
    waveform_ = make_drive_waveform(input, model_.coefficients().drive_amplitude_per_volt, dt_);
    waveform_valid_ = true;
    midpoint_scale_ = 0.5 / std::cos(0.5 * waveform_.angular_frequency_rad_s * dt_);
  }
  const double old_a = waveform_.amplitude_a_v, old_b = waveform_.amplitude_b_v;
  apply_phase_gains();
  // The drive recurrence: a new frequency or phase anchors it at the current phasor, new
  // amplitudes are replayed from its anchor; a new load is not in it.
  if (!same_waveform) {
    drive_recurrence_state_ = RecurrenceState::unanchored;
  } else if (waveform_.amplitude_a_v != old_a || waveform_.amplitude_b_v != old_b) {
    recurrence_inputs_changed();
  }
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
  const double old_a = waveform_.amplitude_a_v, old_b = waveform_.amplitude_b_v;
  const double old_constant = system_.coefficients().preload_constant_force_n;
  faults_ = faults;
  if (faults_.jammed && std::isnan(faults_.jam_position_m)) faults_.jam_position_m = state_.mover_position_m;
  hold_jammed_mover();
  apply_phase_gains();
  // F_P in F_N = max(0, F_P - k_e q1) and the constant back-end term gNP F_P (model_spec §4),
  // mu_s of the guide friction (eqs. 24-25).
  system_.set_preload_factor(model_.coefficients(), faults_.preload_factor);
  system_.set_guide_friction_factor(model_.coefficients(), faults_.guide_friction_factor);
  // The phase gains and the constant preload term are in the drive recurrence.
  if (waveform_.amplitude_a_v != old_a || waveform_.amplitude_b_v != old_b ||
      system_.coefficients().preload_constant_force_n != old_constant) {
    recurrence_inputs_changed();
  }
}

void MotorSimulator::step() { advance(1); }

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
  if (e.network) update_network(q, v, sin_theta, cos_theta, waveform);
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

DriveWaveform MotorSimulator::amplified_waveform() const {
  DriveWaveform waveform = waveform_;
  if (model_.coefficients().effects.network) {
    const double a = waveform_.amplitude_a_v, b = waveform_.amplitude_b_v;
    waveform.amplitude_a_v = a * network_a_.gain.real();
    waveform.quadrature_a_v = a * network_a_.gain.imag();
    waveform.amplitude_b_v = b * network_b_.gain.real();
    waveform.quadrature_b_v = b * network_b_.gain.imag();
    waveform.shifted = true;
    return waveform;
  }
  waveform.amplitude_a_v *= droop_gain_;
  waveform.amplitude_b_v *= droop_gain_;
  return waveform;
}

void MotorSimulator::motional_currents(const MotorSplitSystem::Vector& q, const MotorSplitSystem::Vector& v,
                                       double sin_theta, double cos_theta, double w, Phasor& a, Phasor& b) const {
  // By reciprocity the motional charge per modal displacement is the linear modal force per volt
  // (eqs. 14-15, as the droop effect): I_m = j w (Q_q1 z1 + Q_q2 z2), z the modes' sine phasors.
  const EffectCoefficients& e = model_.coefficients().effects;
  const double inv_w = w > 0.0 ? 1.0 / w : 0.0;
  const Phasor z1 = sine_phasor(q[0] - model_.constants().static_q1_m, v[0] * inv_w, sin_theta, cos_theta);
  const Phasor z2 = sine_phasor(q[1], v[1] * inv_w, sin_theta, cos_theta);
  const Phasor jw{0.0, w};
  a = jw * (e.charge_a_q1 * z1 + e.charge_a_q2 * z2);
  b = jw * (e.charge_b_q1 * z1 + e.charge_b_q2 * z2);
}

void MotorSimulator::update_network(const MotorSplitSystem::Vector& q, const MotorSplitSystem::Vector& v,
                                    double sin_theta, double cos_theta, DriveWaveform& waveform) {
  const OutputNetwork& n = model_.coefficients().effects.output_network;
  const double w = waveform.angular_frequency_rad_s;
  Phasor motional_a, motional_b;
  motional_currents(q, v, sin_theta, cos_theta, w, motional_a, motional_b);
  // Source phasors: A for phase A, B e^{j phase} for phase B (sine phasors on theta).
  const Phasor source_a{waveform_.amplitude_a_v, 0.0};
  const Phasor source_b = waveform_.amplitude_b_v * Phasor{waveform.cos_phase, waveform.sin_phase};
  NetworkPhase next_a = network_a_, next_b = network_b_;
  const double block_s = 64.0 * dt_;
  const bool ok_a = step_network(n, w, block_s, source_a, motional_a, next_a, kLargestNetworkGain);
  const bool ok_b = step_network(n, w, block_s, source_b, motional_b, next_b, kLargestNetworkGain);
  if (ok_a && ok_b) {
    network_a_ = next_a;
    network_b_ = next_b;
  } else {
    ++network_divergence_count_;
  }
  waveform = amplified_waveform();  // the loop's copy differs from waveform_ only in the amplitudes
}

AmplifierReadings MotorSimulator::amplifier_readings() const {
  const EffectCoefficients& e = model_.coefficients().effects;
  OutputNetwork n = e.output_network;
  if (!e.network) n = OutputNetwork{0.0, 0.0, 0.0, model_.coefficients().clamped_capacitance_f};
  const double w = waveform_.angular_frequency_rad_s;
  Phasor motional_a, motional_b;
  motional_currents(MotorSplitSystem::Vector{state_.q1_m, state_.q2_m, state_.mover_position_m},
                    MotorSplitSystem::Vector{state_.q1_dot_m_s, state_.q2_dot_m_s, state_.mover_velocity_m_s},
                    state_.drive_sin, state_.drive_cos, w, motional_a, motional_b);
  const NetworkPhase ideal{Phasor{droop_gain_, 0.0}, Phasor{}, Phasor{}};
  const NetworkPhase& state_a = e.network ? network_a_ : ideal;
  const NetworkPhase& state_b = e.network ? network_b_ : ideal;
  const Phasor source_a{waveform_.amplitude_a_v, 0.0};
  const Phasor source_b = waveform_.amplitude_b_v * Phasor{waveform_.cos_phase, waveform_.sin_phase};
  const double rad_to_deg = 180.0 / std::numbers::pi;
  auto phase = [&](double amplitude_v, Phasor source, const NetworkPhase& state, Phasor motional) {
    AmplifierPhaseReadings r;
    const Phasor gain = state.gain;
    const Phasor terminal = gain * source;
    // I_amp = j w C0 V + I_Lp + I_m, the inductor's current from the network's state.
    const Phasor current = Phasor{0.0, w * n.clamped_capacitance_f} * terminal + state.parallel * source + motional;
    r.current_a = std::abs(current);
    r.terminal_amplitude_v = std::abs(terminal);
    // Relative to the source voltage's phase (a phase without a source: to the commanded one).
    const Phasor reference = amplitude_v > 0.0 ? source / amplitude_v : Phasor{1.0, 0.0};
    r.current_phase_deg = r.current_a > 0.0 ? wrap_phase_deg(std::arg(current / reference) * rad_to_deg) : 0.0;
    r.terminal_phase_deg = wrap_phase_deg(std::arg(gain) * rad_to_deg);
    return r;
  };
  AmplifierReadings readings;
  readings.a = phase(waveform_.amplitude_a_v, source_a, state_a, motional_a);
  readings.b = phase(waveform_.amplitude_b_v, source_b, state_b, motional_b);
  return readings;
}

void MotorSimulator::apply_slow_states() {
  const DoublePair old_stiffness = system_.paired_coefficients().k;  // in the cubic's c1
  const MotorCoefficients& k = model_.coefficients();
  const EffectCoefficients& e = k.effects;
  if (e.thermal) {
    const ThermalFactors f = thermal_factors(e, ambient_offset_k_ + state_.stator_temperature_rise_k);
    system_.set_modal_factors(k, f.stiffness, f.damping);
  }
  if (e.wear) {
    system_.set_friction_coefficient(k.friction_coefficient * wear_friction_factor(e, state_.sliding_distance_m));
  }
  const DoublePair new_stiffness = system_.paired_coefficients().k;
  if (new_stiffness[0] != old_stiffness[0] || new_stiffness[1] != old_stiffness[1]) recurrence_inputs_changed();
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
  drive_recurrence_state_ = RecurrenceState::unanchored;
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
