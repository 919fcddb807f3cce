#include "core/emulator_core.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace swum::emu {

Reason SharedState::submit(Command command) {
  // Amplifier limits are checked by the transports with validate(); here only the queue.
  command.sequence = next_sequence.fetch_add(1, std::memory_order_relaxed);
  if (!commands.try_push(command)) {
    queue_full.fetch_add(1, std::memory_order_relaxed);
    rejects.record(Reason::queue_full, command.source);
    return Reason::queue_full;
  }
  return Reason::none;
}

EmulatorCore::EmulatorCore(const MotorModel& model, CoreConfig config, SharedState& shared)
    : model_(model),
      config_([&] {
        if (!(config.tick_hz > 0.0) || !std::isfinite(config.tick_hz))
          throw std::invalid_argument("tick rate must be positive");
        config.amplifier.tick_s = 1.0 / config.tick_hz;
        config.drive.tick_hz = config.tick_hz;
        config.drive.limits = config.amplifier.limits;
        return config;
      }()),
      shared_(shared),
      amplifier_(config_.amplifier),
      drive_(config_.drive),
      simulator_(model),
      tick_s_(1.0 / config_.tick_hz) {
  const double dt = model.time_step_s();
  if (tick_s_ < dt) throw std::invalid_argument("tick period shorter than the model time step");
  steps_per_tick_ = static_cast<std::uint64_t>(std::llround(tick_s_ / dt));
  const auto window_ticks = static_cast<std::size_t>(std::max(1.0, std::round(config_.speed_window_s / tick_s_)));
  position_ring_.assign(window_ticks + 1, simulator_.state().mover_position_m);
  if (!(config_.electrical_window_s > 0.0) || !std::isfinite(config_.electrical_window_s))
    throw std::invalid_argument("electrical window must be positive");
  electrical_window_ticks_ = static_cast<std::uint64_t>(
      std::max(1.0, std::round(config_.electrical_window_s / tick_s_)));
  config_.sample_stride = std::max(1U, config_.sample_stride);
  simulator_.set_drive(amplifier_.output());
  telemetry_.position_m = simulator_.state().mover_position_m;
  telemetry_.external_clock = config_.external_clock;
}

void EmulatorCore::shut_down() {
  Command off;
  off.fields = Command::kAction;
  off.action = Action::disable;
  amplifier_.apply(off, tick_);
  DriveInput drive = amplifier_.tick(tick_, shared_.enable_line.load(std::memory_order_relaxed));
  simulator_.set_drive(drive);
  telemetry_.state = amplifier_.state();
  telemetry_.output = drive_values(drive);
  shared_.telemetry.store(telemetry_);
}

const Telemetry& EmulatorCore::tick() {
  // 1. Commands accepted since the last boundary, in order.
  Command command;
  accepted_count_ = 0;
  while (shared_.commands.try_pop(command)) {
    if (accepted_count_ < accepted_ns_.size() && command.accepted_ns != 0)
      accepted_ns_[accepted_count_++] = command.accepted_ns;
    if (observer_ != nullptr) observer_->on_command(tick_, command);
    const Reason reason = amplifier_.apply(command, tick_);
    if (reason != Reason::none) shared_.rejects.record(reason, command.source);
    telemetry_.last_sequence = command.sequence;
  }
  // The CiA 402 drive (when a CANopen profile runs it): its commands follow the queue's, so a
  // trace records them in the order they act.
  drive_.tick(shared_.drive_request.load(), amplifier_, telemetry_, tick_, observer_);
  // Run-time faults (the HTTP API) join the scenario's timeline at this boundary.
  // At most what the player holds for one tick: the rest stays queued for the next.
  RuntimeEvent event;
  for (std::size_t n = 0; n < kRuntimeEventCapacity && shared_.runtime_events.try_pop(event); ++n) {
    if (scenario_) scenario_->queue_runtime(event);
  }
  // Scenario: the conditions of this tick (faults that trip the amplifier trip it before its tick).
  if (scenario_) scenario_->set_commanded_load_n(amplifier_.setpoints().load_n);
  conditions_ = scenario_ ? &scenario_->at_tick(tick_) : nullptr;
  if (conditions_ != nullptr) apply_scenario(*conditions_);
  if (scenario_ && scenario_->generation() != published_faults_generation_) {  // rare: a fault starts or ends
    scenario_->active_faults(active_faults_);
    shared_.active_faults.store(active_faults_);
    published_faults_generation_ = scenario_->generation();
  }

  // 2. Amplifier: enable line, watchdog, slew -> drive for this tick.
  const bool enable_line = shared_.enable_line.load(std::memory_order_relaxed);
  if (observer_ != nullptr && last_enable_line_ != static_cast<int>(enable_line)) {
    observer_->on_enable_line(tick_, enable_line);
    last_enable_line_ = static_cast<int>(enable_line);
  }
  DriveInput drive = amplifier_.tick(tick_, enable_line);
  if (conditions_ != nullptr && conditions_->load_n) drive.load_n = *conditions_->load_n;  // the scenario's load
  simulator_.set_drive(drive);

  // 3. Integrate over the tick in fixed sub-steps (sampling the tip every stride steps).
  const double start_position = telemetry_.position_m;  // as reported at the end of the last tick
  const std::uint64_t target_steps = static_cast<std::uint64_t>(
      std::llround(static_cast<double>(tick_ + 1) * tick_s_ / model_.time_step_s()));
  std::uint64_t steps = target_steps - steps_done_;
  double un_min = 1e300, un_max = -1e300, ut_min = 1e300, ut_max = -1e300;
  const std::uint64_t stride = config_.sample_stride;
  for (std::uint64_t done = 0; done < steps;) {
    const std::uint64_t n = std::min(stride, steps - done);
    simulator_.advance(n, electrical_sums_);
    done += n;
    const MotorState& s = simulator_.state();
    const double un = MotorModel::tip_normal_m(s);
    const double ut = model_.tip_tangential_m(s);
    un_min = std::min(un_min, un);
    un_max = std::max(un_max, un);
    ut_min = std::min(ut_min, ut);
    ut_max = std::max(ut_max, ut);
  }
  steps_done_ = target_steps;
  ++tick_;

  // 4. Blow-up guard: the simulator resets itself to rest on NaN/runaway; we latch a fault.
  const MotorState& s = simulator_.state();
  const bool finite = std::isfinite(s.mover_position_m) && std::isfinite(s.mover_velocity_m_s) &&
                      std::isfinite(un_max - un_min) && std::isfinite(ut_max - ut_min);
  if (simulator_.diverged() || !finite) {
    simulator_.clear_diverged();
    if (!finite) simulator_.reset();
    amplifier_.raise_fault(FaultCode::numerical);
    simulator_.set_drive(amplifier_.output());
    ++telemetry_.divergences;
    un_min = un_max = ut_min = ut_max = 0.0;
    electrical_sums_ = ElectricalSums{};
    electrical_ticks_ = 0;
    amplifier_sums_ = protocol::AmplifierOutputValues{};
    terminal_sum_a_ = terminal_sum_b_ = {};
  }

  // 5. Telemetry (what the sensors report: a scenario's sensor faults act here, not on the motor).
  double position = simulator_.state().mover_position_m;
  if (conditions_ != nullptr) report_sensors(*conditions_, position);
  position_ring_[ring_index_] = position;
  const std::size_t n = position_ring_.size();
  ring_index_ = (ring_index_ + 1) % n;
  ring_filled_ = std::min(ring_filled_ + 1, n - 1);
  const std::size_t oldest = (ring_index_ + n - 1 - ring_filled_) % n;
  // ring_index_ now points to the slot after the newest; oldest = ring_filled_ ticks back.
  telemetry_.tick = tick_;
  telemetry_.sim_time_s = simulator_.state().time_s;
  telemetry_.state = amplifier_.state();
  telemetry_.fault = amplifier_.fault();
  telemetry_.enable_line = amplifier_.enable_line();
  telemetry_.at_setpoint = amplifier_.at_setpoint();
  telemetry_.setpoints = amplifier_.setpoints();
  telemetry_.output = drive_values(amplifier_.output());
  if (conditions_ != nullptr && conditions_->load_n) telemetry_.output.load_n = drive.load_n;
  telemetry_.position_m = position;
  telemetry_.tick_speed_m_s = (position - start_position) / tick_s_;
  telemetry_.speed_m_s = ring_filled_
                             ? (position - position_ring_[oldest]) / (static_cast<double>(ring_filled_) * tick_s_)
                             : telemetry_.tick_speed_m_s;
  telemetry_.tip_normal_um = 0.5e6 * (un_max - un_min);
  telemetry_.tip_tangential_um = 0.5e6 * (ut_max - ut_min);
  {
    // The amplifier's output through its network (docs/amplifier.md), summed per tick: the
    // simulator's readings are instantaneous analytic signals that ripple with the contact.
    const AmplifierReadings a = simulator_.amplifier_readings();
    amplifier_sums_.current_a_a += a.a.current_a;
    amplifier_sums_.current_b_a += a.b.current_a;
    amplifier_sums_.current_phase_a_deg += a.a.current_phase_deg;
    amplifier_sums_.current_phase_b_deg += a.b.current_phase_deg;
    amplifier_sums_.terminal_amplitude_a_v += a.a.terminal_amplitude_v;
    amplifier_sums_.terminal_amplitude_b_v += a.b.terminal_amplitude_v;
    constexpr double kDegToRad = std::numbers::pi / 180.0;
    terminal_sum_a_ += std::polar(a.a.terminal_amplitude_v, a.a.terminal_phase_deg * kDegToRad);
    terminal_sum_b_ += std::polar(a.b.terminal_amplitude_v, a.b.terminal_phase_deg * kDegToRad);
  }
  if (++electrical_ticks_ >= electrical_window_ticks_) {
    // No drive, no measurement: a ring-down current at V = 0 has a phase but nothing to refer it to.
    const ElectricalReadings r = drive.amplitude_v > 0.0 ? electrical_readings(electrical_sums_, drive.phase_deg)
                                                         : ElectricalReadings{};
    telemetry_.electrical = {r.current_a_a,          r.current_b_a,          r.phase_a_deg, r.phase_b_deg,
                             r.motional_phase_a_deg, r.motional_phase_b_deg, r.power_a_w,   r.power_b_w};
    protocol::AmplifierOutputValues mean{};
    if (drive.amplitude_v > 0.0) {
      const double n = static_cast<double>(electrical_ticks_);
      const protocol::AmplifierOutputValues& s = amplifier_sums_;
      mean = {s.current_a_a / n,
              s.current_b_a / n,
              s.current_phase_a_deg / n,
              s.current_phase_b_deg / n,
              s.terminal_amplitude_a_v / n,
              s.terminal_amplitude_b_v / n};
      // The amplifier's current from the port's fit of the terminal current (its non-linear
      // coupling terms included; the network's instantaneous readings use the linear motional
      // current, -6 deg off at 400 V: docs/amplifier.md) plus the parallel inductor's current
      // V/(j w L_p) of the window's mean terminal voltage, all relative to the source's phase.
      if (r.valid) {
        const EffectCoefficients& e = simulator_.model().coefficients().effects;
        const double l_p = e.network ? e.output_network.parallel_inductance_h : 0.0;
        const double w = 2.0 * std::numbers::pi * drive.frequency_hz;
        constexpr double kDegToRad = std::numbers::pi / 180.0;
        auto amplifier = [&](double current_a, double phase_deg, std::complex<double> terminal_v) {
          std::complex<double> i = std::polar(current_a, phase_deg * kDegToRad);
          if (l_p > 0.0 && w > 0.0) i += terminal_v / std::complex<double>(0.0, w * l_p);
          return i;
        };
        const std::complex<double> ia = amplifier(r.current_a_a, r.phase_a_deg, terminal_sum_a_ / n);
        const std::complex<double> ib = amplifier(r.current_b_a, r.phase_b_deg, terminal_sum_b_ / n);
        mean.current_a_a = std::abs(ia);
        mean.current_b_a = std::abs(ib);
        mean.current_phase_a_deg = wrap_phase_deg(std::arg(ia) / kDegToRad);
        mean.current_phase_b_deg = wrap_phase_deg(std::arg(ib) / kDegToRad);
      }
    }
    telemetry_.amplifier_output = mean;
    electrical_sums_ = ElectricalSums{};
    electrical_ticks_ = 0;
    amplifier_sums_ = protocol::AmplifierOutputValues{};
    terminal_sum_a_ = terminal_sum_b_ = {};
  }
  telemetry_.stator_temperature_c = kReferenceAmbientC + simulator_.ambient_offset_k() +
                                    simulator_.state().stator_temperature_rise_k;
  telemetry_.cia402 = drive_.values(amplifier_.output());
  telemetry_.applied_commands = amplifier_.applied_commands();
  telemetry_.amplifier_rejects = amplifier_.rejected_commands();
  if (conditions_ != nullptr) report_speed(*conditions_);
  shared_.telemetry.store(telemetry_);
  if (observer_ != nullptr) observer_->on_telemetry(telemetry_);
  if (shared_.recording != nullptr && shared_.recording->on.load(std::memory_order_acquire) &&
      !shared_.recording->ring.try_push(telemetry_))
    shared_.recording->dropped.fetch_add(1, std::memory_order_relaxed);
  return telemetry_;
}

}  // namespace swum::emu

namespace swum::emu {

void EmulatorCore::set_scenario(Scenario scenario, std::FILE* log) {
  for (const ScenarioEvent& e : scenario.events) {
    if (e.type == EventType::ambient && !model_.coefficients().effects.thermal)
      throw std::invalid_argument(e.origin + ": ambient: the parameter file does not enable the thermal effect "
                                             "([effects.thermal])");
  }
  scenario_.emplace(std::move(scenario), config_.tick_hz);
  scenario_log_ = log;
}

void EmulatorCore::apply_scenario(const ScenarioConditions& c) {
  if (scenario_log_ != nullptr) {
    for (const ScenarioEvent* e : c.started)  // rare: an event's start, not every tick
      std::fprintf(scenario_log_, "swum-emu: tick %llu (%.4f s): %s (%s)\n", static_cast<unsigned long long>(tick_),
                   static_cast<double>(tick_) * tick_s_, format_event(*e).c_str(), e->origin.c_str());
  }
  // Amplifier faults that hold trip an enabled amplifier (again after every reset and enable).
  if (amplifier_.state() == AmpState::enabled) {
    if (c.over_current) amplifier_.raise_fault(FaultCode::over_current);
    else if (c.over_temperature) amplifier_.raise_fault(FaultCode::over_temperature);
  }
  // Motor faults: changed only when they change (set_faults is not a per-step call).
  ModelFaults f;
  f.phase_a_gain = c.phase_a_gain;
  f.phase_b_gain = c.phase_b_gain;
  f.preload_factor = c.preload_factor;
  f.guide_friction_factor = c.guide_friction_factor;
  // A jam is a hard stop: without a position the mover stops where it is; with one it runs on
  // until it reaches that position (checked at tick boundaries: it may overshoot by one tick's
  // travel, e.g. 60 um at 0.6 m/s, and is set back onto the stop) and is held there.
  const double position_m = simulator_.state().mover_position_m;
  if (!c.jammed) {
    jam_engaged_ = false;
    jam_target_m_.reset();
  } else if (c.jam_generation != jam_generation_) {  // a new jam
    jam_generation_ = c.jam_generation;
    jam_engaged_ = !c.jam_position_um;
    jam_target_m_ = c.jam_position_um ? *c.jam_position_um * 1e-6 : position_m;
    jam_last_position_m_ = position_m;
  }
  if (c.jammed && !jam_engaged_ && jam_target_m_) {
    const double x = *jam_target_m_;
    jam_engaged_ = (jam_last_position_m_ - x) * (position_m - x) <= 0.0;  // reached or crossed it
    jam_last_position_m_ = position_m;
  }
  f.jammed = c.jammed && jam_engaged_;
  f.jam_position_m = f.jammed ? *jam_target_m_ : faults_.jam_position_m;
  if (c.ambient_c && *c.ambient_c - kReferenceAmbientC != simulator_.ambient_offset_k())
    simulator_.set_ambient_offset_k(*c.ambient_c - kReferenceAmbientC);  // checked to have the thermal effect
  if (f.phase_a_gain != faults_.phase_a_gain || f.phase_b_gain != faults_.phase_b_gain ||
      f.preload_factor != faults_.preload_factor || f.guide_friction_factor != faults_.guide_friction_factor ||
      f.jammed != faults_.jammed || f.jam_position_m != faults_.jam_position_m) {
    simulator_.set_faults(f);  // values were range-checked when the scenario was parsed
    faults_ = f;
  }
  // Communication faults, for the transports.
  shared_.telemetry_silent.store(c.telemetry_silent, std::memory_order_relaxed);
  shared_.modbus_faults.set({.drops_started = c.modbus_drops_started, .delay_ms = c.modbus_delay_ms, .off = false});
  shared_.can_faults.set({.drops_started = 0, .delay_ms = 0.0, .off = c.can_bus_off});
}

void EmulatorCore::report_sensors(const ScenarioConditions& c, double& position_m) {
  // The encoder: the reported position (and so the speed computed from it) stays or is noisy.
  if (c.encoder_stuck) {
    if (!encoder_held_) held_position_m_ = telemetry_.position_m;
    encoder_held_ = true;
    position_m = held_position_m_;
  } else {
    encoder_held_ = false;
  }
  if (c.encoder_sigma_um > 0.0) position_m += c.encoder_sigma_um * 1e-6 * scenario_->normal();
}

void EmulatorCore::report_speed(const ScenarioConditions& c) {
  if (c.speed_frozen) {
    if (!speed_held_) {
      held_speed_m_s_ = telemetry_.speed_m_s;
      held_tick_speed_m_s_ = telemetry_.tick_speed_m_s;
    }
    speed_held_ = true;
    telemetry_.speed_m_s = held_speed_m_s_;
    telemetry_.tick_speed_m_s = held_tick_speed_m_s_;
  } else {
    speed_held_ = false;
  }
  const double offset_m_s = c.speed_bias_mm_s * 1e-3;
  telemetry_.speed_m_s += offset_m_s;
  telemetry_.tick_speed_m_s += offset_m_s;
  if (c.speed_sigma_mm_s > 0.0) {
    const double noise_m_s = c.speed_sigma_mm_s * 1e-3 * scenario_->normal();
    telemetry_.speed_m_s += noise_m_s;
    telemetry_.tick_speed_m_s += noise_m_s;
  }
}

}  // namespace swum::emu
