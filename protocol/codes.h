// The codes every interface of the device carries (docs/protocols.md): amplifier state, fault,
// reject reason and command action. They are wire values: never renumber.
#pragma once

#include <cstdint>

namespace swum::protocol {

enum class AmpState : std::uint8_t { disabled = 0, enabled = 1, fault = 2 };

enum class FaultCode : std::uint8_t {
  none = 0,
  command_timeout = 1,   // watchdog: no valid command for longer than the timeout while enabled
  numerical = 2,         // the model blew up (NaN/Inf, runaway amplitude or speed)
  over_current = 3,      // a shorted phase (scenario phase_short): trips while the short holds
  over_temperature = 4,  // the stator over its limit (scenario over_temperature)
};

// Why a command was rejected (0 = accepted).
enum class Reason : std::uint8_t {
  none = 0,
  frequency_out_of_range = 1,
  amplitude_out_of_range = 2,
  phase_out_of_range = 3,
  load_out_of_range = 4,
  slew_out_of_range = 5,
  unknown_command = 6,      // action / mode code not defined
  bad_checksum = 7,         // CAN CRC
  stale_alive_counter = 8,  // CAN alive counter repeated or went backwards
  wrong_length = 9,         // CAN DLC, Modbus quantity / byte count
  illegal_address = 10,     // Modbus address range not in the map / read-only
  split_value = 11,         // Modbus write covering half of a 32-bit value
  fault_active = 12,        // enable while in fault (reset the fault first)
  enable_line_low = 13,     // enable while the hardware enable input is low
  queue_full = 14,          // command queue full (transport refused it on the spot)
  reserved_bits = 15,       // CAN reserved bits not zero
  illegal_function = 16,    // Modbus function code not supported
  clock_not_external = 17,  // a lockstep step (Modbus advance, CAN SYNC) while the clock is internal
};
inline constexpr std::uint8_t kMaxReason = 17;

const char* to_string(AmpState state);
const char* to_string(FaultCode fault);
const char* to_string(Reason reason);
// The codes as identifiers, for machine-read text (the HTTP API's JSON): the enumerators'
// names ("over_temperature", "slew_out_of_range"), as config/modbus_registers.json's
// reason_codes and docs/scenarios.md name them.
const char* identifier(FaultCode fault);
const char* identifier(Reason reason);

// Command actions; the values are the Modbus command register's codes (holding 0).
// none: a command without an action; as a command of its own it only feeds the watchdog, the
// keep-alive of docs/protocols.md (keep_alive names the same code for the host's clients).
enum class Action : std::uint8_t { none = 0, keep_alive = none, enable = 1, disable = 2, reset_fault = 3 };
inline constexpr std::uint8_t kMaxAction = 3;

enum class CommandSource : std::uint8_t { modbus = 0, can = 1, internal = 2 };

}  // namespace swum::protocol
