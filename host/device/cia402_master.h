// CiA 402's power state machine as the host's master walks it (IEC 61800-7-201 / CiA 402-2,
// "statusword" and "controlword"): the state a statusword shows, the one controlword that moves
// the drive a transition nearer to what the host asked for, and the drive's state and error code
// as the host's DeviceTelemetry reports them. Pure: the CANopen device (canopen_device.cpp) sends
// the words and reads the states back, one transition per exchange, checking each.
#pragma once

#include <cstdint>

#include "codes.h"

namespace swum::host::cia402 {

// CiA 402-2 Table "state coding" (statusword bits 0-3, 5, 6); `unknown` for a word that codes none.
enum class State : std::uint8_t {
  not_ready_to_switch_on,
  switch_on_disabled,
  ready_to_switch_on,
  switched_on,
  operation_enabled,
  quick_stop_active,
  fault_reaction_active,
  fault,
  unknown,
};
[[nodiscard]] State state_of(std::uint16_t statusword);
[[nodiscard]] const char* to_string(State state);

// Controlword commands (CiA 402-2 Table "command coding"; halt, bit 8, is never set).
inline constexpr std::uint16_t kShutdown = 0x06;         // transitions 2, 6, 8: -> ready to switch on
inline constexpr std::uint16_t kSwitchOn = 0x07;         // 3: -> switched on; 5: operation enabled -> switched on
inline constexpr std::uint16_t kEnableOperation = 0x0F;  // 4, 16: -> operation enabled
inline constexpr std::uint16_t kDisableVoltage = 0x00;   // 7, 9, 10, 12: -> switch on disabled
inline constexpr std::uint16_t kFaultReset = 0x80;       // 15 on the rising edge of bit 7: fault -> switch on disabled

// What the host last asked for (DeviceAction): the drive running (operation enabled), or off at
// rest in "ready to switch on" (from where "on" is two transitions away), after a fault reset
// when `reset`. `none`: nothing asked yet (a passive `swum log`): the controlword is left alone.
enum class Goal : std::uint8_t { none, on, off, reset };

// Whether the drive is where `goal` wants it.
[[nodiscard]] bool reached(State state, Goal goal);
// The controlword that takes the drive one transition nearer to `goal` from `state` (it repeats
// `last` when the goal is reached or none): enable 0x06 -> 0x07 -> 0x0F, disable 0x07 -> 0x06,
// a fault reset as the rising edge of bit 7 (0x00 first when the last word held it), nothing
// but 0x00 in fault reaction active (an edge there would be lost) or for a word of no state.
[[nodiscard]] std::uint16_t next_controlword(State state, Goal goal, std::uint16_t last);

// The amplifier state of swum's other protocols: enabled while the drive function is on
// (operation enabled, quick stop active), fault in the two fault states, disabled otherwise.
[[nodiscard]] protocol::AmpState amp_state(State state);
// 0x603F as a swum fault code (docs/canopen.md "Faults and EMCY codes": 0x4310 over_temperature,
// 0x2320 over_current, 0x6100 numerical, 0x8100 command_timeout); any other code is kept as it
// is (above 255, so never taken for a swum code; e.g. 0x8130, the heartbeat error).
[[nodiscard]] int fault_code(std::uint16_t error_code);

}  // namespace swum::host::cia402
