#include "can_telemetry_decode.h"

#include "can_codec.h"

namespace swum::protocol::can {
namespace {
bool full(const CanFrame& f) { return !f.extended && f.dlc == 8; }
template <typename T>
T raw_as(const CanFrame& f, Signal s) {
  return static_cast<T>(raw_value(f, s));
}
}  // namespace

Reason decode_status(const CanFrame& f, StatusFields& out) {
  if (!full(f)) return Reason::wrong_length;
  out.state = raw_as<std::uint8_t>(f, signals::kStatusState);
  out.enable_line = raw_value(f, signals::kStatusEnableLine) != 0;
  out.drive_on = raw_value(f, signals::kStatusDriveOn) != 0;
  out.at_setpoint = raw_value(f, signals::kStatusAtSetpoint) != 0;
  out.external_clock = raw_value(f, signals::kStatusExternalClock) != 0;
  out.fault = raw_as<std::uint8_t>(f, signals::kStatusFault);
  out.last_reject = raw_as<std::uint8_t>(f, signals::kStatusLastReject);
  out.reject_count = raw_as<std::uint8_t>(f, signals::kStatusRejectCount);
  out.applied_count = raw_as<std::uint8_t>(f, signals::kStatusAppliedCount);
  out.status_counter = raw_as<std::uint8_t>(f, signals::kStatusCounter);
  out.stator_temperature_c = physical_value(f, signals::kStatusStatorTemperature);
  return Reason::none;
}

Reason decode_motion(const CanFrame& f, MotionFields& out) {
  if (!full(f)) return Reason::wrong_length;
  out.speed_mm_s = physical_value(f, signals::kMotionSpeed) * 1e-3;      // um/s -> mm/s
  out.position_mm = physical_value(f, signals::kMotionPosition) * 1e-3;  // um -> mm
  return Reason::none;
}

Reason decode_drive(const CanFrame& f, DriveFields& out) {
  if (!full(f)) return Reason::wrong_length;
  out.tip_normal_um = physical_value(f, signals::kDriveTipNormal);
  out.tip_tangential_um = physical_value(f, signals::kDriveTipTangential);
  out.amplitude_v = physical_value(f, signals::kDriveAmplitude);
  out.phase_deg = physical_value(f, signals::kDrivePhase);
  return Reason::none;
}

Reason decode_loop_stats(const CanFrame& f, LoopStatsFields& out) {
  if (!full(f)) return Reason::wrong_length;
  out.lateness_p99_us = physical_value(f, signals::kLoopLatenessP99);
  out.lateness_p999_us = physical_value(f, signals::kLoopLatenessP999);
  out.lateness_max_us = physical_value(f, signals::kLoopLatenessMax);
  out.overruns = raw_as<std::uint32_t>(f, signals::kLoopOverruns);
  return Reason::none;
}

Reason decode_output(const CanFrame& f, OutputFields& out) {
  if (!full(f)) return Reason::wrong_length;
  out.frequency_hz = physical_value(f, signals::kOutputFrequency);
  out.load_n = physical_value(f, signals::kOutputLoad);
  out.lateness_p50_us = physical_value(f, signals::kOutputLatenessP50);
  return Reason::none;
}

Reason decode_clock(const CanFrame& f, ClockFields& out) {
  if (!full(f)) return Reason::wrong_length;
  out.sim_time_s = physical_value(f, signals::kClockTime);
  out.tick = raw_as<std::uint32_t>(f, signals::kClockTick);
  return Reason::none;
}

Reason decode_electrical(const CanFrame& f, ElectricalFields& out) {
  if (!full(f)) return Reason::wrong_length;
  out.current_a = physical_value(f, signals::kElectricalCurrent);
  out.phase_deg = physical_value(f, signals::kElectricalPhase);
  out.motional_phase_deg = physical_value(f, signals::kElectricalMotionalPhase);
  out.power_w = physical_value(f, signals::kElectricalPower);
  return Reason::none;
}

}  // namespace swum::protocol::can
