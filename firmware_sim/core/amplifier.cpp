#include "core/amplifier.h"

#include <algorithm>
#include <cmath>

namespace swum::emu {

namespace {
double slew(double current, double target, double rate_per_s, double dt) {
  if (rate_per_s <= 0.0) return target;
  const double step = rate_per_s * dt;
  return current + std::clamp(target - current, -step, step);
}
}  // namespace

Amplifier::Amplifier(const AmplifierConfig& config) : config_(config) {
  setpoints_.frequency_hz = config.frequency_hz;
  setpoints_.amplitude_v = config.amplitude_v;
  setpoints_.phase_deg = config.phase_deg;
  setpoints_.frequency_slew_hz_per_s = config.frequency_slew_hz_per_s;
  setpoints_.amplitude_slew_v_per_s = config.amplitude_slew_v_per_s;
  output_.amplitude_v = 0.0;
  output_.frequency_hz = config.frequency_hz;
  output_.phase_deg = config.phase_deg;
  output_.load_n = 0.0;
  watchdog_ticks_ = config.watchdog_s > 0.0
                        ? static_cast<std::uint64_t>(std::ceil(config.watchdog_s / config.tick_s - 1e-9))
                        : 0;
}

Reason Amplifier::apply(const Command& c, std::uint64_t tick) {
  Reason reason = validate(c, config_.limits);
  if (reason == Reason::none && (c.fields & Command::kAction) && c.action == Action::enable) {
    if (state_ == AmpState::fault) reason = Reason::fault_active;
    else if (!enable_line_) reason = Reason::enable_line_low;
  }
  if (reason != Reason::none) {
    ++rejected_;
    return reason;
  }
  if (c.fields & Command::kFrequency) setpoints_.frequency_hz = c.frequency_hz;
  if (c.fields & Command::kAmplitude) setpoints_.amplitude_v = c.amplitude_v;
  if (c.fields & Command::kPhase) setpoints_.phase_deg = c.phase_deg;
  if (c.fields & Command::kLoad) setpoints_.load_n = c.load_n;
  if (c.fields & Command::kFrequencySlew) setpoints_.frequency_slew_hz_per_s = c.frequency_slew_hz_per_s;
  if (c.fields & Command::kAmplitudeSlew) setpoints_.amplitude_slew_v_per_s = c.amplitude_slew_v_per_s;
  if (c.fields & Command::kAction) {
    switch (c.action) {
      case Action::none: break;
      case Action::enable:
        if (state_ == AmpState::disabled) {
          state_ = AmpState::enabled;
          output_.amplitude_v = 0.0;  // ramps up from zero at the amplitude slew limit
        }
        break;
      case Action::disable:
        if (state_ == AmpState::enabled) state_ = AmpState::disabled;
        break;
      case Action::reset_fault:
        if (state_ == AmpState::fault) {
          state_ = AmpState::disabled;
          fault_ = FaultCode::none;
        }
        break;
    }
  }
  last_command_tick_ = tick;
  ++applied_;
  return Reason::none;
}

void Amplifier::raise_fault(FaultCode fault) {
  state_ = AmpState::fault;
  fault_ = fault;
  output_.amplitude_v = 0.0;
}

DriveInput Amplifier::tick(std::uint64_t tick, bool enable_line) {
  enable_line_ = enable_line;
  if (state_ == AmpState::enabled && !enable_line) state_ = AmpState::disabled;
  if (state_ == AmpState::enabled && watchdog_ticks_ > 0 && tick > last_command_tick_ + watchdog_ticks_)
    raise_fault(FaultCode::command_timeout);

  const double dt = config_.tick_s;
  output_.phase_deg = setpoints_.phase_deg;
  output_.load_n = setpoints_.load_n;
  if (state_ == AmpState::enabled) {
    output_.frequency_hz = slew(output_.frequency_hz, setpoints_.frequency_hz, setpoints_.frequency_slew_hz_per_s, dt);
    output_.amplitude_v = slew(output_.amplitude_v, setpoints_.amplitude_v, setpoints_.amplitude_slew_v_per_s, dt);
  } else {
    output_.frequency_hz = setpoints_.frequency_hz;  // nothing driven: the oscillator just retunes
    output_.amplitude_v = 0.0;
  }
  return output_;
}

bool Amplifier::at_setpoint() const {
  if (state_ != AmpState::enabled) return output_.amplitude_v == 0.0;
  return output_.amplitude_v == setpoints_.amplitude_v && output_.frequency_hz == setpoints_.frequency_hz;
}

}  // namespace swum::emu
