#include "control/speed_control.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "codes.h"
#include "control/cycle_exchange.h"
#include "formats/number_format.h"

namespace swum::host {
namespace {

std::string fault_name(int code) {
  if (code < 0 || code > 255) return "fault " + std::to_string(code);
  const std::string text = protocol::to_string(static_cast<protocol::FaultCode>(code));
  return text == "?" ? "fault " + std::to_string(code) : text;
}

// What the next cycle sends: the fault reaction's state machine (docs/host.md, "Fault reaction").
class FaultReaction {
 public:
  struct Decision {
    DeviceAction action = DeviceAction::keep_alive;
    bool drive = false;  // false: 0 V
  };

  FaultReaction(const SpeedControlSettings& s, const SpeedControlHooks& hooks, SpeedControlResult& result)
      : settings_(s), hooks_(hooks), result_(result) {}

  // `last` is the telemetry after the previous cycle (or at the start).
  Decision next(const DeviceTelemetry& last, std::uint64_t cycle) {
    if (phase_ == Phase::holdoff) {
      if (holdoff_left_-- > 0) return {DeviceAction::keep_alive, false};
      phase_ = Phase::run;
      ++result_.retries;
      return {DeviceAction::reset_fault, false};
    }
    if (last.is(protocol::AmpState::fault)) return on_fault(last, cycle);
    if (!last.is(protocol::AmpState::enabled)) return {DeviceAction::enable, true};
    return {DeviceAction::keep_alive, true};
  }
  bool stopping() const { return phase_ == Phase::stop; }

 private:
  enum class Phase { run, holdoff, stop };

  Decision on_fault(const DeviceTelemetry& t, std::uint64_t cycle) {
    ++result_.faults_seen;
    const std::string what = "cycle " + std::to_string(cycle) + " (device time " +
                             format_seconds(t.device_time_s.value_or(0.0)) + " s): fault " + fault_name(t.fault_code) +
                             " (code " + std::to_string(t.fault_code) + "): drive off";
    const bool recoverable = settings_.recoverable_faults.contains(t.fault_code);
    if (recoverable && result_.retries < settings_.max_retries) {
      phase_ = Phase::holdoff;
      holdoff_left_ = settings_.holdoff_cycles;
      event(what + "; reset and re-enable after " + std::to_string(settings_.holdoff_cycles) + " cycles (retry " +
            std::to_string(result_.retries + 1) + " of " + std::to_string(settings_.max_retries) + ")");
    } else {
      phase_ = Phase::stop;
      result_.stop_reason = "fault " + fault_name(t.fault_code) + " (code " + std::to_string(t.fault_code) +
                            ") at cycle " + std::to_string(cycle) +
                            (recoverable ? ": --max-retries " + std::to_string(settings_.max_retries) + " used up"
                                         : ": not recoverable (--recover)");
      event(what + "; stopping: " + result_.stop_reason);
    }
    return {DeviceAction::disable, false};
  }
  void event(const std::string& line) const {
    if (hooks_.on_event) hooks_.on_event(line);
  }

  const SpeedControlSettings& settings_;
  const SpeedControlHooks& hooks_;
  SpeedControlResult& result_;
  Phase phase_ = Phase::run;
  int holdoff_left_ = 0;
};

void check_settings(const SpeedControlSettings& s) {
  if (!std::isfinite(s.target_mm_s)) throw std::invalid_argument("--speed-mm-s: must be a number");
  if (!(s.frequency_hz > 0.0)) throw std::invalid_argument("--frequency-hz: must be > 0");
  if (!(s.cycle_s > 0.0 && s.cycle_s <= 10.0)) throw std::invalid_argument("--cycle-ms: must be within (0, 10000]");
  if (!(s.duration_s >= s.cycle_s && s.duration_s <= 1e6))
    throw std::invalid_argument("--duration-s: must be at least one cycle and <= 1e6 s");
  if (!(s.tick_hz > 0.0)) throw std::invalid_argument("--tick-hz: must be > 0");
  if (s.holdoff_cycles < 0) throw std::invalid_argument("--holdoff-cycles: must be >= 0");
  if (s.max_retries < 0) throw std::invalid_argument("--max-retries: must be >= 0");
}

// The cycles of one run: decide (fault reaction, PI), exchange, report the row.
void run_cycles(CycleExchange& exchange, FaultReaction& reaction, DriveSetpoint& setpoint, DeviceTelemetry last,
                const SpeedControlSettings& s, const SpeedControlHooks& hooks, SpeedControlResult& result) {
  SpeedPi pi(s.gains);
  const auto cycles = static_cast<std::uint64_t>(std::llround(s.duration_s / s.cycle_s));
  double error_sum_mm_s = 0.0;
  std::uint64_t error_count = 0;
  for (std::uint64_t cycle = 0; cycle < cycles && !reaction.stopping(); ++cycle) {
    if (hooks.stop_requested && hooks.stop_requested()) {
      result.stop_reason = "interrupted";
      break;
    }
    const FaultReaction::Decision d = reaction.next(last, cycle);
    if (!d.drive) pi.reset();
    setpoint.amplitude_v = d.drive ? pi.update(s.target_mm_s, last.speed_mm_s, s.cycle_s) : 0.0;
    last = exchange.exchange(setpoint, d.action);
    result.cycles = cycle + 1;
    if (hooks.on_row) {
      hooks.on_row({cycle, last.tick, last.device_time_s.value_or(exchange.host_seconds(last)), s.target_mm_s,
                    last.speed_mm_s, setpoint.amplitude_v, s.frequency_hz, last.state, last.fault_code, d.action});
    }
    if (2 * cycle >= cycles) {
      error_sum_mm_s += std::abs(s.target_mm_s - last.speed_mm_s);
      ++error_count;
    }
  }
  if (error_count > 0) result.mean_abs_error_last_half_mm_s = error_sum_mm_s / static_cast<double>(error_count);
}

}  // namespace

const char* action_name(DeviceAction action) {
  switch (action) {
    case DeviceAction::keep_alive: return "keep_alive";
    case DeviceAction::enable: return "enable";
    case DeviceAction::disable: return "disable";
    case DeviceAction::reset_fault: return "reset_fault";
  }
  return "?";
}

std::string format_speed_control_row(const SpeedControlRow& r) {
  char tick[24] = "";
  if (r.tick) std::snprintf(tick, sizeof tick, "%" PRIu64, *r.tick);
  // printf_string: a --speed-mm-s of 1e300 is 308 characters through %.6f; the row is never cut.
  return printf_string("%" PRIu64 ",%s,%.6f,%.6f,%.6f,%.6f,%.6f,%d,%d,%s\n", r.cycle, tick, r.time_s, r.target_mm_s,
                       r.speed_mm_s, r.amplitude_v_command, r.frequency_hz, r.state, r.fault_code,
                       action_name(r.action));
}

SpeedControlResult run_speed_control(Device& device, const SpeedControlSettings& s, const SpeedControlHooks& hooks) {
  check_settings(s);
  CycleExchange exchange(device, s.cycle_s, s.tick_hz, s.slew);
  SpeedControlResult result;
  FaultReaction reaction(s, hooks, result);
  DriveSetpoint setpoint;
  setpoint.frequency_hz = s.frequency_hz;
  setpoint.phase_deg = s.target_mm_s < 0.0 ? -90.0 : 90.0;
  try {
    run_cycles(exchange, reaction, setpoint, device.read(), s, hooks, result);
  } catch (const DeviceError&) {
    try {
      exchange.drive_off(setpoint);
    } catch (const DeviceError&) {
      // The device does not answer: its watchdog switches the drive off.
    }
    throw;
  }
  if (!reaction.stopping()) exchange.drive_off(setpoint);  // a stop on a fault has sent it already
  return result;
}

}  // namespace swum::host
