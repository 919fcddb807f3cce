#include "track/track_run.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "codes.h"
#include "control/cycle_exchange.h"
#include "formats/number_format.h"

namespace swum::host {
namespace {

std::string fault_text(int code) {
  const std::string name = code >= 0 && code <= 255 ? protocol::to_string(static_cast<protocol::FaultCode>(code))
                                                    : std::string("?");
  return (name == "?" ? "fault" : name) + " (code " + std::to_string(code) + ")";
}

// The cycles of one run; the caller switches the drive off afterwards.
void run_cycles(CycleExchange& exchange, ResonanceTracker& tracker, const TrackRunSettings& s,
                const TrackRunHooks& hooks, TrackRunResult& result) {
  auto event = [&hooks](const std::string& line) {
    if (!line.empty() && hooks.on_event) hooks.on_event(line);
  };
  DriveSetpoint setpoint;
  setpoint.amplitude_v = s.amplitude_v;
  setpoint.phase_deg = s.drive_phase_deg;
  TrackDecision decision = tracker.start();
  event(describe(decision.event));
  const auto cycles = static_cast<std::uint64_t>(std::llround(s.duration_s / s.cycle_s));
  DeviceAction action = DeviceAction::enable;
  int not_enabled = 0;
  for (std::uint64_t cycle = 0; cycle < cycles; ++cycle) {
    if (hooks.stop_requested && hooks.stop_requested()) {
      result.stop_reason = "interrupted";
      return;
    }
    setpoint.frequency_hz = decision.frequency_hz;
    const DeviceTelemetry t = exchange.exchange(setpoint, action);
    action = DeviceAction::keep_alive;
    result.cycles = cycle + 1;
    TrackRow row;
    row.cycle = cycle;
    row.time_s = t.device_time_s.value_or(exchange.host_seconds(t));
    row.mode = decision.mode;
    row.frequency_hz = setpoint.frequency_hz;
    row.speed_mm_s = t.speed_mm_s;
    row.electrical = t.electrical;
    row.stator_temperature_c = t.stator_temperature_c;
    row.state = t.state;
    row.fault_code = t.fault_code;
    if (hooks.on_row) hooks.on_row(row);
    if (t.is(protocol::AmpState::fault)) {
      result.stop_reason = fault_text(t.fault_code) + " at cycle " + std::to_string(cycle);
      return;
    }
    if (!t.is(protocol::AmpState::enabled)) {
      // A wall-time board applies the enable a tick after it reads it: ask again, and give up only
      // after enable_cycles (an enable line held low, a board that refuses).
      if (++not_enabled > s.enable_cycles) {
        result.stop_reason = "the device is not enabled after " + std::to_string(s.enable_cycles) + " cycles (cycle " +
                             std::to_string(cycle) + "; enable line low?)";
        return;
      }
      action = DeviceAction::enable;
      continue;  // the tracker sees only cycles with the drive on
    }
    not_enabled = 0;
    TrackSample sample;
    sample.time_s = row.time_s;
    sample.speed_mm_s = t.speed_mm_s;
    if (t.electrical) sample.motional_phase_deg = t.electrical->motional_phase_a_deg;
    decision = tracker.next(sample);
    if (decision.status != TrackStatus::ok) {
      result.stop_reason = failure_text(decision);
      return;
    }
    event(describe(decision.event));
  }
}

}  // namespace

std::string check(const TrackRunSettings& s) {
  if (!(s.amplitude_v > 0.0 && s.amplitude_v <= 10000.0)) return "--amplitude-v: must be in (0, 10000]";
  if (!(std::abs(s.drive_phase_deg) <= 180.0) || s.drive_phase_deg == 0.0)
    return "--drive-phase-deg: must be in -180..180 and not 0 (its sign is the direction)";
  if (!(s.cycle_s > 0.0 && s.cycle_s <= 10.0)) return "--cycle-ms: must be within (0, 10000]";
  if (!(s.duration_s >= s.cycle_s && s.duration_s <= 1e6))
    return "--duration-s: must be at least one cycle and <= 1e6 s";
  if (!(s.tick_hz > 0.0 && s.tick_hz <= 1e6)) return "--tick-hz: must be in (0, 1e6]";
  if (!(s.slew.frequency_hz_per_s >= 0.0 && s.slew.frequency_hz_per_s <= 1e9))
    return "--frequency-slew-hz-per-s: must be in 0..1e9 Hz/s";
  if (!(s.slew.amplitude_v_per_s >= 0.0 && s.slew.amplitude_v_per_s <= 1e9))
    return "--amplitude-slew-v-per-s: must be in 0..1e9 V/s";
  if (s.tracker.method == TrackMethod::phase && s.drive_phase_deg < 0.0)
    return "--method phase: only the forward drive (--drive-phase-deg > 0) is characterised: phase A's motional "
           "phase sits 40 deg lower when reversed (docs/host.md)";
  if (s.tracker.direction != (s.drive_phase_deg > 0.0 ? 1.0 : -1.0)) return "direction: must follow --drive-phase-deg";
  return check(s.tracker);
}

std::string format_track_row(const TrackRow& r) {
  // printf_string throughout: a row is never cut, whatever a device reports (%.6f of 1e300).
  std::string electrical = ",,,,";
  if (r.electrical) {
    const protocol::ElectricalValues& e = *r.electrical;
    electrical = printf_string("%.3f,%.3f,%.6f,%.6f,%.4f", e.motional_phase_a_deg, e.phase_a_deg, e.current_a_a,
                               e.current_b_a, e.power_w());
  }
  std::string temperature;
  if (r.stator_temperature_c) temperature = printf_string("%.3f", *r.stator_temperature_c);
  return printf_string("%" PRIu64 ",%.6f,%s,%.3f,%.3f,%s,%s,%d,%d\n", r.cycle, r.time_s, mode_name(r.mode),
                       r.frequency_hz, r.speed_mm_s, electrical.c_str(), temperature.c_str(), r.state, r.fault_code);
}

TrackRunResult run_track(Device& device, const TrackRunSettings& s, const TrackRunHooks& hooks) {
  const std::string problem = check(s);
  if (!problem.empty()) throw std::invalid_argument(problem);
  ResonanceTracker tracker(s.tracker);
  CycleExchange exchange(device, s.cycle_s, s.tick_hz, s.slew);
  TrackRunResult result;
  DriveSetpoint off;
  off.phase_deg = s.drive_phase_deg;
  try {
    run_cycles(exchange, tracker, s, hooks, result);
    off.frequency_hz = tracker.frequency_hz();
    exchange.drive_off(off);
  } catch (...) {
    // A device error, or a hook's (the log could not be written): the drive goes off first.
    try {
      off.frequency_hz = tracker.frequency_hz();
      exchange.drive_off(off);
    } catch (const DeviceError&) {
      // The device does not answer: its watchdog switches the drive off.
    }
    throw;
  }
  result.peak_hz = tracker.peak_hz();
  result.phase_setpoint_deg = tracker.phase_setpoint_deg();
  result.final_frequency_hz = tracker.frequency_hz();
  result.collapses = tracker.collapses();
  return result;
}

}  // namespace swum::host
