// Controller-side decoding of the emulator's CAN telemetry frames (the inverse of the
// encode_* functions of can_codec.h, same bit layout as config/swum.dbc). Pure; used by the
// host tool's CAN adapter and kept honest by an encode -> decode round-trip test.
#pragma once

#include <cstdint>

#include "can_frame.h"
#include "codes.h"

namespace swum::protocol::can {

struct StatusFields {
  std::uint8_t state = 0;  // AmpState
  bool enable_line = false;
  bool drive_on = false;
  bool at_setpoint = false;
  bool external_clock = false;        // lockstep: telemetry only at SYNC
  std::uint8_t fault = 0;             // FaultCode
  std::uint8_t last_reject = 0;       // Reason
  std::uint8_t reject_count = 0;      // mod 256
  std::uint8_t applied_count = 0;     // mod 256
  std::uint8_t status_counter = 0;    // mod 256, +1 per telemetry set
  double stator_temperature_c = 0.0;  // bytes 6-7 (0 from a sender that leaves them free)
};
struct MotionFields {
  double speed_mm_s = 0.0;
  double position_mm = 0.0;
};
struct DriveFields {
  double tip_normal_um = 0.0;
  double tip_tangential_um = 0.0;
  double amplitude_v = 0.0;
  double phase_deg = 0.0;
};
struct LoopStatsFields {
  double lateness_p99_us = 0.0;
  double lateness_p999_us = 0.0;
  double lateness_max_us = 0.0;
  std::uint32_t overruns = 0;  // saturates at 65535
};
struct OutputFields {
  double frequency_hz = 0.0;
  double load_n = 0.0;
  double lateness_p50_us = 0.0;
};

struct ClockFields {
  double sim_time_s = 0.0;  // ms resolution, wraps after 2^32 ms
  std::uint32_t tick = 0;
};

// ElectricalA / ElectricalB (one phase each; the identifier says which).
struct ElectricalFields {
  double current_a = 0.0;  // peak of the drive-frequency component
  double phase_deg = 0.0;  // current vs voltage, + = current leads
  double motional_phase_deg = 0.0;
  double power_w = 0.0;
};

// Reason::wrong_length unless the frame is a standard 8-byte frame (the only failure a
// telemetry frame has); Reason::none and `out` filled otherwise.
Reason decode_status(const CanFrame& frame, StatusFields& out);
Reason decode_motion(const CanFrame& frame, MotionFields& out);
Reason decode_drive(const CanFrame& frame, DriveFields& out);
Reason decode_loop_stats(const CanFrame& frame, LoopStatsFields& out);
Reason decode_output(const CanFrame& frame, OutputFields& out);
Reason decode_clock(const CanFrame& frame, ClockFields& out);
Reason decode_electrical(const CanFrame& frame, ElectricalFields& out);

}  // namespace swum::protocol::can
