// `swum control`'s loop (docs/host.md, "swum control"): the amplitude PI of speed_pi.h at a
// fixed drive frequency, one exchange with the device per cycle, and the documented fault
// reaction. In lockstep (swum-emu --clock external) each cycle steps the device by exactly
// cycle x tick rate ticks, so two runs give identical rows; on a wall-time device the cycles
// run on the host clock (not reproducible).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <string>

#include "controllers/speed_pi.h"
#include "device/device.h"

namespace swum::host {

// Fault codes recovered from by default (reset + re-enable after the hold-off): only the
// command timeout, which says the link hiccupped, not that the motor or the model is unsafe.
// numerical (2) and the planned over_current (3) / over_temperature (4) stop the run.
inline const std::set<int> kDefaultRecoverableFaults{1};

struct SpeedControlSettings {
  double target_mm_s = 0.0;  // the sign is the direction (phase +90 / -90 deg)
  double frequency_hz = 40000.0;
  double duration_s = 1.0;
  double cycle_s = 0.001;
  double tick_hz = 10000.0;  // lockstep: the device's tick rate (checked against its clock)
  SpeedPiGains gains;
  DriveSlew slew;
  std::set<int> recoverable_faults = kDefaultRecoverableFaults;
  int holdoff_cycles = 10;  // drive-off cycles between a recoverable fault and its reset
  int max_retries = 3;      // recoveries allowed in one run
};

struct SpeedControlRow {
  std::uint64_t cycle = 0;
  std::optional<std::uint64_t> tick;  // device ticks completed (empty when not carried)
  double time_s = 0.0;                // device time (host time since start when not carried)
  double target_mm_s = 0.0;
  double speed_mm_s = 0.0;
  double amplitude_v_command = 0.0;
  double frequency_hz = 0.0;
  int state = 0;
  int fault_code = 0;
  DeviceAction action = DeviceAction::keep_alive;
};

struct SpeedControlResult {
  std::uint64_t cycles = 0;
  double mean_abs_error_last_half_mm_s = 0.0;
  int faults_seen = 0;
  int retries = 0;
  std::string stop_reason;  // empty when the run completed, else why it stopped (one line)
};

inline constexpr const char* kSpeedControlCsvHeader =
    "cycle,tick,time_s,target_mm_s,speed_mm_s,amplitude_v_command,frequency_hz,state,fault_code,action\n";
// One CSV row, fixed precision (%.6f): identical telemetry gives identical bytes.
std::string format_speed_control_row(const SpeedControlRow& row);
const char* action_name(DeviceAction action);

struct SpeedControlHooks {
  std::function<void(const SpeedControlRow&)> on_row;
  std::function<void(const std::string&)> on_event;  // fault reaction, one line each
  std::function<bool()> stop_requested;              // Ctrl-C: drive off, return "interrupted"
};

// Runs the loop for duration / cycle cycles; the drive is switched off when it returns or
// throws a DeviceError (when the device still answers). Throws std::invalid_argument for
// settings that cannot run.
SpeedControlResult run_speed_control(Device& device, const SpeedControlSettings& settings,
                                     const SpeedControlHooks& hooks);

}  // namespace swum::host
