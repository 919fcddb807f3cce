// The CiA 402 power drive system's state machine (IEC 61800-7-201, CiA 402-2 "PDS FSA") as pure
// functions: the controlword's commands, the transitions 0-16, the statusword of each state, the
// quick stop option code's behaviour (0x605A) and the swum faults' error codes (0x603F). No state
// of its own: Cia402Drive (core/cia402_drive.h) keeps the state and acts on the amplifier.
#pragma once

#include <array>
#include <cstdint>

#include "codes.h"

namespace swum::emu {

// CiA 402-2 Figure "state machine"; the values are what Cia402Values::state carries.
enum class Cia402State : std::uint8_t {
  not_ready_to_switch_on = 0,
  switch_on_disabled = 1,
  ready_to_switch_on = 2,
  switched_on = 3,
  operation_enabled = 4,
  quick_stop_active = 5,
  fault_reaction_active = 6,
  fault = 7,
};
const char* to_string(Cia402State state);

// The controlword's device control commands (CiA 402-2 Table "command coding", bits 7 and 3-0).
// One code has two names: 0xxx 0111 is "switch on" (transition 3) and "disable operation" (5);
// 0xxx 1111 is "enable operation" (4, 16) and, from ready to switch on, "switch on + enable
// operation" (3 + 4). Bit 7 set is no command of its own: a fault reset is its rising edge
// (DriveRequest::fault_reset_edges), and while it is held no other command is decoded.
enum class Cia402Command : std::uint8_t {
  none,              // bit 7 held
  shutdown,          // 0xxx x110: 2, 6, 8
  switch_on,         // 0xxx 0111: 3, 5
  enable_operation,  // 0xxx 1111: 3 + 4, 4, 16
  disable_voltage,   // 0xxx xx0x: 7, 9, 10, 12
  quick_stop,        // 0xxx x01x: 7, 10, 11
};
[[nodiscard]] Cia402Command decode_controlword(std::uint16_t controlword);

// Controlword bits besides the command (CiA 402-2 "controlword").
inline constexpr std::uint16_t kControlwordFaultReset = 1U << 7;
inline constexpr std::uint16_t kControlwordHalt = 1U << 8;

// What a quick stop does (0x605A; CiA 402-2 "quick stop option code"): which deceleration, and
// whether the drive then leaves quick stop active for switch on disabled (transition 12) or
// stays there, powered at standstill, until "enable operation" (16) or "disable voltage" (12).
enum class QuickStopRamp : std::uint8_t {
  none,                     // 0: disable the drive function at once (the mover coasts)
  profile_deceleration,     // 1, 5: 0x6084
  quick_stop_deceleration,  // 2, 6: 0x6085
};
struct QuickStopBehaviour {
  QuickStopRamp ramp = QuickStopRamp::quick_stop_deceleration;
  bool stays_in_quick_stop_active = false;
};
// 0, 1, 2, 5 and 6 are supported (0x605A's range in docs/canopen.md); any other value, which the
// profile refuses to store, behaves as the default 2.
[[nodiscard]] QuickStopBehaviour quick_stop_behaviour(std::int16_t option);
[[nodiscard]] bool quick_stop_option_supported(std::int16_t option);

// What decides a step besides the controlword.
struct Cia402Inputs {
  Cia402Command command = Cia402Command::none;
  bool fault_reset_edge = false;     // a rising edge of bit 7 since the last step
  bool fault = false;                // a fault to react to (transition 13)
  bool quick_stop_finished = false;  // quick stop active: the ramp has reached standstill
  std::int16_t quick_stop_option = 2;
  // Quick stop active entered by the device itself (0x6007 = 3): the master's "enable operation"
  // still latched from before does not count as a new command for transition 16.
  bool enable_operation_is_stale = false;
};

inline constexpr std::int8_t kNoTransition = -1;
struct Cia402Step {
  Cia402State state = Cia402State::not_ready_to_switch_on;
  // The transitions taken, in order (CiA 402-2 numbers; kNoTransition where none): at most two,
  // 3 + 4 ("switch on + enable operation") and 11 + 12 (quick stop with option 0).
  std::array<std::int8_t, 2> transitions{kNoTransition, kNoTransition};
  [[nodiscard]] bool changed() const { return transitions[0] != kNoTransition; }
};

// One step from `state`. Transition 0 (power on) is where a drive starts, 1 (self-test passed)
// is taken from not ready to switch on at the first step, 14 (fault reaction done) at the step
// after 13. A fault takes 13 from every state but the two fault states; in fault only the reset
// edge acts (15).
[[nodiscard]] Cia402Step next_state(Cia402State state, const Cia402Inputs& inputs);

// Statusword bits besides the state's (CiA 402-2 "statusword").
inline constexpr std::uint16_t kStatuswordVoltageEnabled = 1U << 4;
inline constexpr std::uint16_t kStatuswordQuickStop = 1U << 5;  // 0: quick stop active
inline constexpr std::uint16_t kStatuswordWarning = 1U << 7;
inline constexpr std::uint16_t kStatuswordRemote = 1U << 9;
inline constexpr std::uint16_t kStatuswordTargetReached = 1U << 10;
inline constexpr std::uint16_t kStatuswordInternalLimit = 1U << 11;
inline constexpr std::uint16_t kStatuswordModeBit12 = 1U << 12;  // profile velocity: speed = 0
inline constexpr std::uint16_t kStatuswordModeBit13 = 1U << 13;  // profile velocity: max slippage
// The state's bits 0-3, 5, 6 (CiA 402-2 Table "state coding") with bit 4 voltage enabled set
// where the amplifier may drive (ready to switch on to quick stop active) and bit 9 remote
// always set (the controlword is processed): e.g. switch on disabled 0x0240, operation enabled
// 0x0237, fault 0x0208.
[[nodiscard]] std::uint16_t state_statusword(Cia402State state);

struct Cia402StatusFlags {
  bool warning = false;
  bool target_reached = false;
  bool internal_limit = false;
  bool mode_bit12 = false;
  bool mode_bit13 = false;
};
[[nodiscard]] std::uint16_t statusword(Cia402State state, const Cia402StatusFlags& flags);

// 0x603F / EMCY error codes (CiA 301 Table "emergency error codes", CiA 402-2 Annex): the swum
// faults of docs/canopen.md "Faults and EMCY codes", 0 for none; a code outside FaultCode gives
// 0x1000 (generic error).
[[nodiscard]] std::uint16_t error_code(protocol::FaultCode fault);
inline constexpr std::uint16_t kErrorCodeGeneric = 0x1000;
inline constexpr std::uint16_t kErrorCodeHeartbeat = 0x8130;  // a consumed heartbeat lost, 0x6007 = 1

// The modes this drive supports (0x6502: 0x00010004): 3 profile velocity, -1 open loop.
inline constexpr std::int8_t kModeNone = 0;
inline constexpr std::int8_t kModeProfileVelocity = 3;
inline constexpr std::int8_t kModeOpenLoop = -1;
[[nodiscard]] bool mode_supported(std::int8_t mode);

}  // namespace swum::emu
