// One device exchange per control cycle, shared by `swum control` and `swum track`: in lockstep
// (swum-emu --clock external) a step that sets the drive, runs exactly the cycle's ticks and
// returns the telemetry after them (two runs give identical rows); on a wall-time device the
// set-point and action at the cycle's deadline on the host clock, then a read.
#pragma once

#include <chrono>
#include <cstdint>

#include "device/device.h"

namespace swum::host {

class CycleExchange {
 public:
  // Throws std::invalid_argument ("--cycle-ms: ...") when a lockstep cycle is not a whole number
  // of ticks in 1..65535 at tick_hz.
  CycleExchange(Device& device, double cycle_s, double tick_hz, const DriveSlew& slew);

  [[nodiscard]] bool lockstep() const { return lockstep_; }
  // Host seconds since the exchange was made (for devices that carry no clock).
  [[nodiscard]] double host_seconds(const DeviceTelemetry& t) const;
  // Throws DeviceError; in lockstep also when the device's clock does not match tick_hz.
  DeviceTelemetry exchange(const DriveSetpoint& setpoint, DeviceAction action);
  // The drive off (end of a run: completed, interrupted, stopped on a fault).
  void drive_off(DriveSetpoint setpoint);

 private:
  void check_tick_rate(const DeviceTelemetry& t) const;

  Device& device_;
  double cycle_s_;
  double tick_hz_;
  DriveSlew slew_;
  bool lockstep_ = false;
  std::uint32_t ticks_per_cycle_ = 0;
  std::uint64_t cycles_ = 0;
  std::chrono::steady_clock::time_point start_;
};

// "%.6f" text of seconds (the control logs' and messages' format).
[[nodiscard]] std::string format_seconds(double seconds);

}  // namespace swum::host
