// The device state every interface reports (Modbus input registers, CAN telemetry frames): one
// snapshot per tick, in physical units. The emulator publishes it; the codecs encode it.
#pragma once

#include <cstdint>

#include "codes.h"
#include "command.h"

namespace swum::protocol {

// What the amplifier drives this tick.
struct DriveValues {
  double amplitude_v = 0.0;
  double frequency_hz = 0.0;
  double phase_deg = 0.0;
  double load_n = 0.0;
};

// The loop's timing figures the interfaces carry (refreshed about 10 times per second).
struct LoopTiming {
  std::uint64_t overruns = 0;
  std::uint64_t lateness_p50_ns = 0, lateness_p99_ns = 0, lateness_p999_ns = 0, lateness_max_ns = 0;
  std::uint64_t compute_p99_ns = 0, compute_max_ns = 0;
};

// What the amplifier measures at its two outputs over the last electrical window (1 ms by
// default; docs/protocols.md "Electrical port"): per phase the drive-frequency component of the
// current, its phase relative to that phase's voltage (+ = current leads), the phase of the
// motional current (the clamped capacitance C0 compensated: what a resonance tracker locks on)
// and the real power.
struct ElectricalValues {
  double current_a_a = 0.0, current_b_a = 0.0;  // peak amplitude (A)
  double phase_a_deg = 0.0, phase_b_deg = 0.0;
  double motional_phase_a_deg = 0.0, motional_phase_b_deg = 0.0;
  double power_a_w = 0.0, power_b_w = 0.0;
  [[nodiscard]] double power_w() const { return power_a_w + power_b_w; }  // both phases
};

// The amplifier's own output through its output network (docs/amplifier.md; the motor's
// parameter file's [amplifier] section): per phase the amplitude of the current the amplifier
// delivers and its phase relative to the source voltage (+ = leads), and the terminal voltage
// amplitude. Without a network the amplifier current is the phase current (C0's and the motional
// one) and the terminal amplitude the commanded one.
struct AmplifierOutputValues {
  double current_a_a = 0.0, current_b_a = 0.0;  // peak amplitude (A)
  double current_phase_a_deg = 0.0, current_phase_b_deg = 0.0;
  double terminal_amplitude_a_v = 0.0, terminal_amplitude_b_v = 0.0;
};

// The CiA 402 drive's published values (docs/canopen.md "State machine", "Modes"): what the
// CANopen profile maps into 0x6041, 0x6061, 0x603F, 0x2011 and 0x2030. Values only (protocol/
// knows nothing of the drive): `state` is the drive's canopen::Cia402State as a number.
struct Cia402Values {
  bool active = false;                 // a CiA 402 profile drives the amplifier (otherwise the rest is 0)
  std::uint16_t statusword = 0;        // 0x6041
  std::int8_t mode_display = 0;        // 0x6061
  std::uint16_t error_code = 0;        // 0x603F
  std::uint8_t state = 0;              // Cia402State
  double velocity_demand_m_s = 0.0;    // profile velocity: the ramp's output the speed loop follows
  double tracking_frequency_hz = 0.0;  // 0x2030: the resonance tracker's frequency (0: not tracked yet)
  double terminal_amplitude_v = 0.0;   // 0x2011: the amplifier's output as the terminals' amplitude
};

struct Telemetry {
  std::uint64_t tick = 0;
  double sim_time_s = 0.0;
  AmpState state = AmpState::disabled;
  FaultCode fault = FaultCode::none;
  bool enable_line = true;
  bool at_setpoint = true;
  AmplifierSetpoints setpoints;
  DriveValues output;           // what the amplifier drives this tick
  double speed_m_s = 0.0;       // mover speed, mean over the last speed window (10 ms)
  double tick_speed_m_s = 0.0;  // mean over the last tick
  double position_m = 0.0;
  double tip_normal_um = 0.0;      // (max - min)/2 of u_tip over the last tick
  double tip_tangential_um = 0.0;  // (max - min)/2 of w_tip over the last tick
  std::uint64_t applied_commands = 0;
  std::uint64_t amplifier_rejects = 0;
  std::uint64_t last_sequence = 0;  // sequence of the last command applied
  std::uint64_t divergences = 0;
  bool external_clock = false;  // lockstep: time advances only when a controller steps it
  ElectricalValues electrical;
  AmplifierOutputValues amplifier_output;
  double stator_temperature_c = 20.0;  // ambient plus the thermal effect's rise (ambient alone without it)
  LoopTiming stats;
  Cia402Values cia402;
};

// The last reject reason (any interface) and the running count of rejects.
struct RejectSnapshot {
  Reason last = Reason::none;
  std::uint64_t count = 0;
};

// Status bits (Modbus input register 0; the CAN Status frame carries the same flags).
inline constexpr std::uint16_t kStatusEnabled = 1U << 0;
inline constexpr std::uint16_t kStatusFault = 1U << 1;
inline constexpr std::uint16_t kStatusEnableLine = 1U << 2;
inline constexpr std::uint16_t kStatusDriveOn = 1U << 3;
inline constexpr std::uint16_t kStatusAtSetpoint = 1U << 4;
// The drive is on when the amplifier is enabled and drives a non-zero amplitude.
inline bool drive_on(const Telemetry& t) { return t.state == AmpState::enabled && t.output.amplitude_v > 0.0; }

}  // namespace swum::protocol
