// The CiA 402 drive's inputs (docs/canopen.md): what a CANopen master last wrote into the drive
// objects (RPDO or SDO), latched by the CANopen profile on its receive thread and read by the
// loop at every tick boundary (SharedState::drive_request, a Seqlock), so that the power state
// machine and the drive's control laws run at the tick rate while SDO, NMT and PDO handling stay
// off the tick. Values in the bus's units (µm/s, µm/s², 0.01°, mHz, mV): the drive converts once.
#pragma once

#include <cstdint>

namespace swum::emu {

struct DriveRequest {
  bool active = false;                                 // a CiA 402 profile is in use (otherwise the drive does nothing)
  std::uint16_t controlword = 0;                       // 0x6040
  std::uint32_t fault_reset_edges = 0;                 // rising edges of controlword bit 7 seen so far (none is missed)
  std::int8_t mode = 0;                                // 0x6060: 0 none, 3 profile velocity, -1 open loop
  std::int32_t target_velocity_um_s = 0;               // 0x60FF
  std::uint32_t profile_acceleration_um_s2 = 2000000;  // 0x6083
  std::uint32_t profile_deceleration_um_s2 = 2000000;  // 0x6084
  std::uint32_t quick_stop_deceleration_um_s2 = 10000000;  // 0x6085
  std::int16_t quick_stop_option = 2;                      // 0x605A
  std::uint16_t velocity_window_um_s = 10000;              // 0x606D
  std::uint16_t velocity_window_time_ms = 50;              // 0x606E
  std::int16_t abort_connection_option = 1;                // 0x6007: reaction to comm_loss_events
  std::uint32_t comm_loss_events = 0;                      // heartbeat consumer timeouts so far
  // Mode -1 (open loop): the amplifier's set-points.
  std::uint32_t frequency_mhz = 40000000;           // 0x2001
  std::uint32_t amplitude_mv = 0;                   // 0x2002: terminal amplitude (half peak-to-peak)
  std::int16_t phase_cdeg = 9000;                   // 0x2003
  std::uint32_t frequency_slew_hz_per_s = 1000000;  // 0x2004
  std::uint32_t amplitude_slew_v_per_s = 100000;    // 0x2005
  // Profile velocity: the resonance tracker's motional phase set-point.
  std::int16_t motional_phase_setpoint_cdeg = 1500;  // 0x2031
};

}  // namespace swum::emu
