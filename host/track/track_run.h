// `swum track`'s loop on a live device (docs/host.md, "swum track"): one exchange per control
// cycle (lockstep with swum-emu --clock external: exact and reproducible), the tracker's next
// frequency, one row per cycle. A fault, a device error or Ctrl-C end the run with the drive off.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "controllers/resonance_tracker.h"
#include "device/device.h"

namespace swum::host {

struct TrackRunSettings {
  TrackSettings tracker;
  double amplitude_v = 0.0;
  double drive_phase_deg = 90.0;  // V_B ahead of V_A (the direction)
  double duration_s = 60.0;
  double cycle_s = 0.02;
  double tick_hz = 10000.0;  // lockstep: the device's tick rate (checked against its clock)
  DriveSlew slew;            // written to the device (0 = unlimited)
  int enable_cycles = 50;    // cycles a drive that is not (yet) enabled is asked again before the run stops
};

// The telemetry after one cycle at frequency_hz and what the tracker did in it.
struct TrackRow {
  std::uint64_t cycle = 0;
  double time_s = 0.0;  // device time (host time since the start when not carried)
  TrackMode mode = TrackMode::search;
  double frequency_hz = 0.0;  // driven during the cycle
  double speed_mm_s = 0.0;
  std::optional<protocol::ElectricalValues> electrical;
  std::optional<double> stator_temperature_c;
  int state = 0;
  int fault_code = 0;
};

inline constexpr const char* kTrackCsvHeader =
    "cycle,time_s,mode,frequency_hz,speed_mm_s,motional_phase_a_deg,phase_a_deg,current_a_a,current_b_a,power_w,"
    "stator_temperature_c,state,fault_code\n";
// One CSV row, fixed precision: identical telemetry gives identical bytes. Electrical cells are
// empty when the device does not report them.
[[nodiscard]] std::string format_track_row(const TrackRow& row);

struct TrackRunResult {
  std::uint64_t cycles = 0;
  std::optional<double> peak_hz;             // the last peak a search found
  std::optional<double> phase_setpoint_deg;  // phase method
  double final_frequency_hz = 0.0;
  int collapses = 0;
  std::string stop_reason;  // empty when the run completed, else one line ("interrupted", a fault)
};

struct TrackRunHooks {
  std::function<void(const TrackRow&)> on_row;
  std::function<void(const std::string&)> on_event;
  std::function<bool()> stop_requested;  // Ctrl-C
};

// One line naming the first bad setting (its option), empty when usable: the command checks
// before it connects or creates a file.
[[nodiscard]] std::string check(const TrackRunSettings& settings);

// Throws std::invalid_argument for settings that cannot run; whatever ends the run early
// (DeviceError, an output write error thrown by a hook) is rethrown after the drive was switched
// off if the device still answers.
TrackRunResult run_track(Device& device, const TrackRunSettings& settings, const TrackRunHooks& hooks);

}  // namespace swum::host
