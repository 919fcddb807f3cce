// The CiA 402 drive profile's wire codes (IEC 61800-7-201, CiA 402-2), one codec for both ends of
// the bus: the power drive system's states and their statusword coding, the controlword's bits,
// command words and their decoding, the modes of operation, and the swum faults' error codes
// (0x603F). The drive (firmware_sim/core/cia402_state, its state machine) encodes with it; the
// host's master (host/device/cia402_master, its walk) decodes with it. Pure, no allocation.
#pragma once

#include <cstdint>
#include <optional>

#include "codes.h"

namespace swum::canopen {

// CiA 402-2 Figure "state machine"; the values 0-7 are what Cia402Values::state carries.
// `unknown`: a statusword that codes none of them (state_of), never a drive's state.
enum class Cia402State : std::uint8_t {
  not_ready_to_switch_on = 0,
  switch_on_disabled = 1,
  ready_to_switch_on = 2,
  switched_on = 3,
  operation_enabled = 4,
  quick_stop_active = 5,
  fault_reaction_active = 6,
  fault = 7,
  unknown = 8,
};
[[nodiscard]] const char* to_string(Cia402State state);

// Statusword bits besides the state's (CiA 402-2 "statusword").
inline constexpr std::uint16_t kStatuswordVoltageEnabled = 1U << 4;
inline constexpr std::uint16_t kStatuswordQuickStop = 1U << 5;  // 0: quick stop active
inline constexpr std::uint16_t kStatuswordWarning = 1U << 7;
inline constexpr std::uint16_t kStatuswordRemote = 1U << 9;
inline constexpr std::uint16_t kStatuswordTargetReached = 1U << 10;
inline constexpr std::uint16_t kStatuswordInternalLimit = 1U << 11;
inline constexpr std::uint16_t kStatuswordModeBit12 = 1U << 12;  // profile velocity: speed = 0
inline constexpr std::uint16_t kStatuswordModeBit13 = 1U << 13;  // profile velocity: max slippage

// A state's statusword as swum's drive writes it: the state's bits 0-3, 5, 6 (CiA 402-2 Table
// "state coding") with bit 4 voltage enabled set where the amplifier may drive (ready to switch
// on to quick stop active) and bit 9 remote always set (the controlword is processed): e.g.
// switch on disabled 0x0240, operation enabled 0x0237, fault 0x0208; a value of no state (unknown)
// gives 0x0200.
[[nodiscard]] std::uint16_t state_statusword(Cia402State state);
// The state a statusword codes, by the same table (bits 0-3, 5, 6 under each state's mask; the
// other bits are ignored); unknown for a word that codes none.
[[nodiscard]] Cia402State state_of(std::uint16_t statusword);

// Controlword bits (CiA 402-2 "controlword"): the command's bits 0-3 and 7, and halt.
inline constexpr std::uint16_t kControlwordSwitchOnBit = 1U << 0;
inline constexpr std::uint16_t kControlwordEnableVoltageBit = 1U << 1;
inline constexpr std::uint16_t kControlwordQuickStopBit = 1U << 2;  // 0: quick stop
inline constexpr std::uint16_t kControlwordEnableOperationBit = 1U << 3;
inline constexpr std::uint16_t kControlwordFaultReset = 1U << 7;  // its rising edge: transition 15
inline constexpr std::uint16_t kControlwordHalt = 1U << 8;

// The command words a master sends (CiA 402-2 Table "command coding", the don't-care bits clear).
inline constexpr std::uint16_t kControlwordShutdown = 0x0006;         // 2, 6, 8: -> ready to switch on
inline constexpr std::uint16_t kControlwordSwitchOn = 0x0007;         // 3, 5: -> switched on
inline constexpr std::uint16_t kControlwordEnableOperation = 0x000F;  // 4, 16, 3 + 4: -> operation enabled
inline constexpr std::uint16_t kControlwordDisableVoltage = 0x0000;   // 7, 9, 10, 12: -> switch on disabled
inline constexpr std::uint16_t kControlwordQuickStop = 0x0002;        // 7, 10, 11

// The controlword's device control commands (CiA 402-2 Table "command coding", bits 7 and 3-0).
// One code has two names: 0xxx 0111 is "switch on" (transition 3) and "disable operation" (5);
// 0xxx 1111 is "enable operation" (4, 16) and, from ready to switch on, "switch on + enable
// operation" (3 + 4). Bit 7 set is no command of its own: a fault reset is its rising edge (the
// drive watches for it), and while it is held no other command is decoded.
enum class Cia402Command : std::uint8_t {
  none,              // bit 7 held
  shutdown,          // 0xxx x110: 2, 6, 8
  switch_on,         // 0xxx 0111: 3, 5
  enable_operation,  // 0xxx 1111: 3 + 4, 4, 16
  disable_voltage,   // 0xxx xx0x: 7, 9, 10, 12
  quick_stop,        // 0xxx x01x: 7, 10, 11
};
[[nodiscard]] Cia402Command decode_controlword(std::uint16_t controlword);

// Modes of operation (0x6060, 0x6061; CiA 402-2 "modes of operation"). swum's drive supports
// 3 profile velocity and -1 open loop (a manufacturer-specific mode), 0x6502 = 0x00010004.
inline constexpr std::int8_t kModeNone = 0;
inline constexpr std::int8_t kModeProfileVelocity = 3;
inline constexpr std::int8_t kModeOpenLoop = -1;
[[nodiscard]] bool mode_supported(std::int8_t mode);

// 0x603F / EMCY error codes (CiA 301 Table "emergency error codes", CiA 402-2 Annex) of the swum
// faults (docs/canopen.md "Faults and EMCY codes"), one table both ways: 0 for none; a value
// outside FaultCode gives the generic error 0x1000.
[[nodiscard]] std::uint16_t error_code(protocol::FaultCode fault);
// The swum fault an error code stands for; none (no value) for a code of no swum fault, e.g.
// 0x1000 or 0x8130, the heartbeat error.
[[nodiscard]] std::optional<protocol::FaultCode> fault_of(std::uint16_t error_code);
inline constexpr std::uint16_t kErrorCodeGeneric = 0x1000;
inline constexpr std::uint16_t kErrorCodeHeartbeat = 0x8130;  // a consumed heartbeat lost, 0x6007 = 1

}  // namespace swum::canopen
