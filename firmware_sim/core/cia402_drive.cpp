#include "core/cia402_drive.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/emulator_core.h"

namespace swum::emu {

// The wire codes the drive reads and writes (canopen/cia402.h).
using canopen::decode_controlword;
using canopen::error_code;
using canopen::kControlwordHalt;
using canopen::kErrorCodeHeartbeat;
using canopen::kModeNone;
using canopen::kModeOpenLoop;
using canopen::kModeProfileVelocity;
using canopen::mode_supported;

namespace {

double move_toward(double value, double target, double step) { return value + std::clamp(target - value, -step, step); }

// Profile velocity's ramp: the acceleration while the speed's magnitude grows, the deceleration
// while it shrinks, and through zero at the deceleration down and the acceleration up.
double ramp(double demand_m_s, double target_m_s, double acceleration_m_s2, double deceleration_m_s2, double dt) {
  const bool reverses = target_m_s * demand_m_s < 0.0;
  if (demand_m_s != 0.0 && (reverses || std::abs(target_m_s) < std::abs(demand_m_s)))
    return move_toward(demand_m_s, reverses ? 0.0 : target_m_s, deceleration_m_s2 * dt);
  return move_toward(demand_m_s, target_m_s, acceleration_m_s2 * dt);
}

bool drives(Cia402State state) {
  return state == Cia402State::operation_enabled || state == Cia402State::quick_stop_active;
}

Cia402DriveConfig checked(Cia402DriveConfig c) {
  if (!(c.tick_hz > 0.0) || !std::isfinite(c.tick_hz))
    throw std::invalid_argument("CiA 402 drive: tick rate must be positive");
  if (!(c.control_cycle_s > 0.0 && c.control_cycle_s <= 1.0))
    throw std::invalid_argument("CiA 402 drive: control cycle must be within (0, 1] s");
  if (!(c.drive_phase_deg > 0.0 && c.drive_phase_deg <= c.limits.max_abs_phase_deg))
    throw std::invalid_argument("CiA 402 drive: drive phase must be within (0, the amplifier's phase limit]");
  if (c.tracker_cycles < 1 || c.tracker_cycles > 1000)
    throw std::invalid_argument("CiA 402 drive: tracker cycles must be within 1..1000");
  if (!(c.tracker_min_amplitude_v >= 0.0))
    throw std::invalid_argument("CiA 402 drive: tracker minimum amplitude_v must be >= 0");
  if (!(c.frequency_slew_hz_per_s >= 0.0 && c.frequency_slew_hz_per_s <= c.limits.max_frequency_slew_hz_per_s) ||
      !(c.amplitude_slew_v_per_s >= 0.0 && c.amplitude_slew_v_per_s <= c.limits.max_amplitude_slew_v_per_s))
    throw std::invalid_argument("CiA 402 drive: slews must be within the amplifier's limits");
  c.speed_gains.max_amplitude_v = std::min(c.speed_gains.max_amplitude_v, c.limits.max_amplitude_v);
  // The tracker: the phase method, locked on the request's set-point, within the amplifier's range.
  c.tracker.method = TrackMethod::phase;
  c.tracker.direction = 1.0;  // the drive feeds it the speed along the drive direction
  c.tracker.min_hz = std::max(c.tracker.min_hz, c.limits.min_frequency_hz);
  c.tracker.max_hz = std::min(c.tracker.max_hz, c.limits.max_frequency_hz);
  c.tracker.start_hz = std::clamp(c.tracker.start_hz, c.tracker.min_hz, c.tracker.max_hz);
  if (!c.tracker.phase_setpoint_deg) c.tracker.phase_setpoint_deg = 15.0;
  return c;
}

}  // namespace

Cia402Drive::Cia402Drive(const Cia402DriveConfig& config)
    : config_(checked(config)), pi_(config_.speed_gains), tracker_(config_.tracker) {
  cycle_ticks_ = static_cast<std::uint64_t>(std::max(1.0, std::round(config_.control_cycle_s * config_.tick_hz)));
  cycle_s_ = static_cast<double>(cycle_ticks_) / config_.tick_hz;
}

Reason Cia402Drive::apply(Amplifier& amplifier, Command command, std::uint64_t tick) {
  command.source = CommandSource::can;
  if (observer_ != nullptr) observer_->on_command(tick, command);
  ++commands_issued_;
  const Reason reason = amplifier.apply(command, tick);
  command_refused_ = reason != Reason::none;
  if (command_refused_) ++commands_refused_;
  return reason;
}

void Cia402Drive::tick(const DriveRequest& r, Amplifier& amplifier, const Telemetry& last, std::uint64_t tick,
                       TickObserver* observer) {
  observer_ = observer;
  if (!r.active) {
    if (active_ && amplifier.state() == AmpState::enabled) {
      Command off;
      off.fields = Command::kAction;
      off.action = Action::disable;
      apply(amplifier, off, tick);
    }
    active_ = false;
    state_ = Cia402State::not_ready_to_switch_on;
    error_code_ = 0;
    return;
  }
  if (!active_) {  // transition 0: the drive starts; the events before it are not its own
    active_ = true;
    state_ = Cia402State::not_ready_to_switch_on;
    seen_fault_reset_edges_ = r.fault_reset_edges;
    seen_comm_loss_events_ = r.comm_loss_events;
  }
  const bool reset_edge = r.fault_reset_edges != seen_fault_reset_edges_;
  const bool comm_loss = r.comm_loss_events != seen_comm_loss_events_;
  seen_fault_reset_edges_ = r.fault_reset_edges;
  seen_comm_loss_events_ = r.comm_loss_events;

  Cia402Command command = decode_controlword(r.controlword);
  if (command != Cia402Command::enable_operation) enable_operation_is_stale_ = false;  // the master spoke again
  // Heartbeat loss: CiA 402-2 0x6007 (abort connection option code).
  bool heartbeat_fault = false;
  bool heartbeat_quick_stop = false;
  // The reaction acts on a running drive only (as drives do, e.g. a master's NMT reset
  // communication at its own start must not fault a drive at rest): operation enabled.
  if (comm_loss && state_ == Cia402State::operation_enabled) {
    switch (r.abort_connection_option) {
      case 1: heartbeat_fault = true; break;
      case 2: command = Cia402Command::disable_voltage; break;
      case 3:
        command = Cia402Command::quick_stop;
        heartbeat_quick_stop = true;
        break;
      default: break;  // 0: no action (manufacturer values below 0: none defined)
    }
  }
  // Transition 15 needs the fault gone: the amplifier's latch is reset first.
  if (state_ == Cia402State::fault && reset_edge && amplifier.state() == AmpState::fault) {
    Command reset;
    reset.fields = Command::kAction;
    reset.action = Action::reset_fault;
    apply(amplifier, reset, tick);
  }
  const bool amplifier_fault = amplifier.state() == AmpState::fault;

  Cia402Inputs in;
  in.command = command;
  in.fault_reset_edge = reset_edge;
  in.fault = amplifier_fault || (heartbeat_fault && state_ != Cia402State::fault);
  in.quick_stop_finished = quick_stop_finished_;
  in.quick_stop_option = r.quick_stop_option;
  in.enable_operation_is_stale = enable_operation_is_stale_;
  const Cia402Step step = next_state(state_, in);
  if (step.state == Cia402State::fault_reaction_active)
    error_code_ = amplifier_fault ? error_code(amplifier.fault()) : kErrorCodeHeartbeat;
  if (step.state == Cia402State::switch_on_disabled && state_ == Cia402State::fault) error_code_ = 0;
  if (step.changed()) enter(step.state, amplifier, last, tick);
  if (heartbeat_quick_stop && state_ == Cia402State::quick_stop_active) enable_operation_is_stale_ = true;
  // The amplifier switched off under the drive (its enable line went low): the drive's power
  // is gone, as after "disable voltage".
  if (drives(state_) && amplifier.state() == AmpState::disabled)
    enter(Cia402State::switch_on_disabled, amplifier, last, tick);

  mode_display_ = mode_supported(r.mode) ? r.mode : kModeNone;
  if (drives(state_)) {
    if (ticks_to_cycle_ == 0) {
      control_cycle(r, amplifier, last, tick);
      ticks_to_cycle_ = cycle_ticks_;
    }
    --ticks_to_cycle_;
  }
  update_flags(r, amplifier, last);
  observer_ = nullptr;
}

void Cia402Drive::enter(Cia402State next, Amplifier& amplifier, const Telemetry& last, std::uint64_t tick) {
  const Cia402State previous = state_;
  state_ = next;
  if (next == Cia402State::operation_enabled && previous == Cia402State::quick_stop_active) return;  // 16: on already
  if (next == Cia402State::operation_enabled) {  // 4: the amplifier on at 0 V; the first cycle runs now
    Command on;
    on.fields = Command::kAction | Command::kAmplitude;
    on.action = Action::enable;
    on.amplitude_v = 0.0;
    if (apply(amplifier, on, tick) != Reason::none) {
      state_ = Cia402State::switch_on_disabled;  // the enable line is low: no power to enable
      return;
    }
    mode_started_ = false;
    ticks_to_cycle_ = 0;
    in_window_ticks_ = 0;
    restart_loops(last);
    return;
  }
  if (next == Cia402State::quick_stop_active) {
    quick_stop_finished_ = false;
    return;  // the amplifier stays on for the ramp down
  }
  // Every other state leaves the amplifier off (in the fault states it is off or latched).
  if (amplifier.state() == AmpState::enabled) {
    Command off;
    off.fields = Command::kAction | Command::kAmplitude;
    off.action = Action::disable;
    off.amplitude_v = 0.0;
    apply(amplifier, off, tick);
  }
  restart_loops(last);
  velocity_demand_m_s_ = 0.0;
  quick_stop_finished_ = false;
}

void Cia402Drive::restart_loops(const Telemetry& last) {
  pi_.reset();
  tracking_ = false;
  amplitude_v_ = 0.0;
  internal_limit_ = false;
  // The demand starts where the mover is (a mode change while it moves), so the ramp is smooth.
  velocity_demand_m_s_ = drives(state_) ? last.speed_m_s : 0.0;
  if (velocity_demand_m_s_ != 0.0) direction_ = velocity_demand_m_s_ > 0.0 ? 1.0 : -1.0;
}

void Cia402Drive::start_tracker(double start_hz, double setpoint_deg) {
  // Every setting within check()'s ranges (the configuration's were checked at construction):
  // the constructor has nothing to refuse, so it neither throws nor builds a message here.
  TrackSettings s = config_.tracker;
  s.start_hz = std::clamp(start_hz, s.min_hz, s.max_hz);
  s.phase_setpoint_deg = std::clamp(setpoint_deg, -90.0, kMaxPhaseSetpointDeg);
  tracker_ = ResonanceTracker(s);
  const TrackDecision d = tracker_.start();
  frequency_hz_ = d.frequency_hz;
  tracker_mode_ = d.mode;
  tracker_setpoint_deg_ = setpoint_deg;
  tracker_countdown_ = config_.tracker_cycles;
  tracking_ = true;
  tracked_once_ = true;
}

void Cia402Drive::control_cycle(const DriveRequest& r, Amplifier& amplifier, const Telemetry& last,
                                std::uint64_t tick) {
  if (!mode_started_ || r.mode != mode_) {  // a mode starts from empty loops
    mode_ = r.mode;
    mode_started_ = true;
    restart_loops(last);
  }
  internal_limit_ = false;
  switch (mode_) {
    case kModeProfileVelocity: profile_velocity_cycle(r, amplifier, last, tick); break;
    case kModeOpenLoop: open_loop_cycle(r, amplifier, tick); break;
    default: {  // none, or not supported: 0 V (the command also feeds the amplifier's watchdog)
      Command zero;
      zero.fields = Command::kAmplitude;
      zero.amplitude_v = 0.0;
      apply(amplifier, zero, tick);
      quick_stop_finished_ = true;
      break;
    }
  }
}

void Cia402Drive::profile_velocity_cycle(const DriveRequest& r, Amplifier& amplifier, const Telemetry& last,
                                         std::uint64_t tick) {
  const bool quick_stop = state_ == Cia402State::quick_stop_active;
  const bool halt = (r.controlword & kControlwordHalt) != 0;
  const double target_m_s = quick_stop || halt ? 0.0 : r.target_velocity_um_s * 1e-6;
  double deceleration_m_s2 = r.profile_deceleration_um_s2 * 1e-6;
  if (quick_stop && quick_stop_behaviour(r.quick_stop_option).ramp == QuickStopRamp::quick_stop_deceleration)
    deceleration_m_s2 = r.quick_stop_deceleration_um_s2 * 1e-6;
  velocity_demand_m_s_ = ramp(velocity_demand_m_s_, target_m_s, r.profile_acceleration_um_s2 * 1e-6, deceleration_m_s2,
                              cycle_s_);
  quick_stop_finished_ = velocity_demand_m_s_ == 0.0;
  if (velocity_demand_m_s_ != 0.0) direction_ = velocity_demand_m_s_ > 0.0 ? 1.0 : -1.0;

  // The speed loop: the amplitude from the demand and the measured speed (the 10 ms mean).
  const double speed_mm_s = last.speed_m_s * 1e3;
  amplitude_v_ = pi_.update(velocity_demand_m_s_ * 1e3, speed_mm_s, cycle_s_);
  internal_limit_ = amplitude_v_ >= config_.speed_gains.max_amplitude_v;

  // The frequency: the tracker, from above whenever the demand leaves 0 (at 0 V there is no phase
  // to lock on, and the resonance of a small amplitude lies higher than that of a large one).
  const double setpoint_deg = r.motional_phase_setpoint_cdeg * 0.01;
  if (velocity_demand_m_s_ == 0.0) {
    tracking_ = false;
  } else if (!tracking_) {
    start_tracker(config_.tracker.start_hz, setpoint_deg);
  } else if (setpoint_deg != tracker_setpoint_deg_) {
    start_tracker(frequency_hz_, setpoint_deg);  // a new set-point (0x2031): approached from here
  } else if (--tracker_countdown_ <= 0) {
    tracker_countdown_ = config_.tracker_cycles;
    if (last.output.amplitude_v >= config_.tracker_min_amplitude_v) {
      // Reversed, phase B leads: its motional phase is what phase A's is forward (the motor's
      // symmetry), so one set-point serves both directions.
      TrackSample sample;
      sample.time_s = static_cast<double>(tick) / config_.tick_hz;
      sample.speed_mm_s = direction_ * speed_mm_s;
      sample.motional_phase_deg = direction_ > 0.0 ? last.electrical.motional_phase_a_deg
                                                   : last.electrical.motional_phase_b_deg;
      const TrackDecision d = tracker_.next(sample);
      if (d.status != TrackStatus::ok) {
        start_tracker(config_.tracker.start_hz, setpoint_deg);  // collapsed too often: again from above
      } else {
        frequency_hz_ = d.frequency_hz;
        tracker_mode_ = d.mode;
      }
    }
  }

  Command c;
  c.fields = Command::kFrequency | Command::kAmplitude | Command::kPhase | Command::kFrequencySlew |
             Command::kAmplitudeSlew;
  c.frequency_hz = frequency_hz_;
  c.amplitude_v = amplitude_v_;
  c.phase_deg = direction_ * config_.drive_phase_deg;
  c.frequency_slew_hz_per_s = config_.frequency_slew_hz_per_s;
  c.amplitude_slew_v_per_s = config_.amplitude_slew_v_per_s;
  apply(amplifier, c, tick);
}

void Cia402Drive::open_loop_cycle(const DriveRequest& r, Amplifier& amplifier, std::uint64_t tick) {
  const AmplifierLimits& limits = config_.limits;
  // Out-of-range set-points (the profile refuses them, so only a bad mapping gets here) are held
  // at the limits and shown as "internal limit active", never refused: a refused command would
  // also starve the amplifier's watchdog.
  auto within = [this](double value, double low, double high) {
    const double held = std::clamp(value, low, high);
    if (held != value) internal_limit_ = true;
    return held;
  };
  // Quick stop and halt: the amplitude down to 0 V at the amplitude slew (0x2005).
  const bool stop = state_ == Cia402State::quick_stop_active || (r.controlword & kControlwordHalt) != 0;
  Command c;
  c.fields = Command::kFrequency | Command::kAmplitude | Command::kPhase | Command::kFrequencySlew |
             Command::kAmplitudeSlew;
  c.frequency_hz = within(r.frequency_mhz * 1e-3, limits.min_frequency_hz, limits.max_frequency_hz);
  c.amplitude_v = stop ? 0.0 : within(r.amplitude_mv * 1e-3, 0.0, limits.max_amplitude_v);
  c.phase_deg = within(r.phase_cdeg * 0.01, -limits.max_abs_phase_deg, limits.max_abs_phase_deg);
  c.frequency_slew_hz_per_s = within(r.frequency_slew_hz_per_s, 0.0, limits.max_frequency_slew_hz_per_s);
  c.amplitude_slew_v_per_s = within(r.amplitude_slew_v_per_s, 0.0, limits.max_amplitude_slew_v_per_s);
  apply(amplifier, c, tick);
  amplitude_v_ = c.amplitude_v;
  frequency_hz_ = c.frequency_hz;
  quick_stop_finished_ = amplifier.output().amplitude_v == 0.0;
}

void Cia402Drive::update_flags(const DriveRequest& r, const Amplifier& amplifier, const Telemetry& last) {
  flags_ = {};
  const bool running = drives(state_);
  flags_.warning = !amplifier.enable_line() || command_refused_ ||
                   (running && (!mode_supported(mode_) && mode_ != kModeNone)) ||
                   (running && mode_ == kModeProfileVelocity && tracking_ && tracker_mode_ == TrackMode::recover);
  flags_.internal_limit = running && internal_limit_;
  if (running && mode_ == kModeProfileVelocity) {
    // Target reached (bit 10): within the velocity window 0x606D for the window time 0x606E, of
    // the target or, halted or quick-stopping, of standstill. Bit 12: the speed is 0 (within the
    // window: the velocity threshold objects 0x606F/0x6070 are not in the dictionary).
    const bool to_zero = state_ == Cia402State::quick_stop_active || (r.controlword & kControlwordHalt) != 0;
    const double reference_m_s = to_zero ? 0.0 : r.target_velocity_um_s * 1e-6;
    const double window_m_s = r.velocity_window_um_s * 1e-6;
    in_window_ticks_ = std::abs(last.speed_m_s - reference_m_s) <= window_m_s ? in_window_ticks_ + 1 : 0;
    const auto window_ticks = static_cast<std::uint64_t>(
        std::llround(r.velocity_window_time_ms * 1e-3 * config_.tick_hz));
    flags_.target_reached = in_window_ticks_ > window_ticks;
    flags_.mode_bit12 = std::abs(last.speed_m_s) <= window_m_s;
  } else {
    in_window_ticks_ = 0;
    if (running && mode_ == kModeOpenLoop) flags_.target_reached = amplifier.at_setpoint();
  }
}

protocol::Cia402Values Cia402Drive::values(const DriveInput& output) const {
  protocol::Cia402Values v;
  if (!active_) return v;
  v.active = true;
  v.statusword = statusword(state_, flags_);
  v.mode_display = mode_display_;
  v.error_code = error_code_;
  v.state = static_cast<std::uint8_t>(state_);
  v.velocity_demand_m_s = velocity_demand_m_s_;
  v.tracking_frequency_hz = tracked_once_ ? tracker_.frequency_hz() : 0.0;
  v.terminal_amplitude_v = output.amplitude_v;
  return v;
}

}  // namespace swum::emu
