// The virtual two-phase amplifier: a pure state machine (no clock, no I/O, no allocation).
// Time is counted in loop ticks. Commands arrive from the transports through the command queue
// and are applied, in order, at the tick boundary; tick() then yields the drive input that the
// motor model integrates over the coming tick.
//
//   disabled --enable--> enabled --disable / enable line low--> disabled
//   enabled --watchdog timeout / numerical blow-up--> fault --reset_fault--> disabled
//
// Reason and fault codes are part of the wire protocols (docs/protocols.md): never renumber.
#pragma once

#include <cstdint>

#include "model/motor_model.h"

namespace swum::emu {

enum class AmpState : std::uint8_t { disabled = 0, enabled = 1, fault = 2 };

enum class FaultCode : std::uint8_t {
  none = 0,
  command_timeout = 1,  // watchdog: no valid command for longer than the timeout while enabled
  numerical = 2,        // the model blew up (NaN/Inf, runaway amplitude or speed)
};

// Why a command was rejected (0 = accepted).
enum class Reason : std::uint8_t {
  none = 0,
  frequency_out_of_range = 1,
  amplitude_out_of_range = 2,
  phase_out_of_range = 3,
  load_out_of_range = 4,
  slew_out_of_range = 5,
  unknown_command = 6,       // action / mode code not defined
  bad_checksum = 7,          // CAN CRC
  stale_alive_counter = 8,   // CAN alive counter repeated or went backwards
  wrong_length = 9,          // CAN DLC, Modbus quantity / byte count
  illegal_address = 10,      // Modbus address range not in the map / read-only
  split_value = 11,          // Modbus write covering half of a 32-bit value
  fault_active = 12,         // enable while in fault (reset the fault first)
  enable_line_low = 13,      // enable while the hardware enable input is low
  queue_full = 14,           // command queue full (transport refused it on the spot)
  reserved_bits = 15,        // CAN reserved bits not zero
  illegal_function = 16,     // Modbus function code not supported
};

const char* to_string(AmpState state);
const char* to_string(FaultCode fault);
const char* to_string(Reason reason);

enum class Action : std::uint8_t { none = 0, enable = 1, disable = 2, reset_fault = 3 };
inline constexpr std::uint8_t kMaxAction = 3;

enum class CommandSource : std::uint8_t { modbus = 0, can = 1, internal = 2 };

// A (partial) command: only the fields flagged in `fields` are changed. Action `none` with no
// fields is a keep-alive (feeds the watchdog).
struct Command {
  static constexpr std::uint32_t kAction = 1U << 0;
  static constexpr std::uint32_t kFrequency = 1U << 1;
  static constexpr std::uint32_t kAmplitude = 1U << 2;
  static constexpr std::uint32_t kPhase = 1U << 3;
  static constexpr std::uint32_t kLoad = 1U << 4;
  static constexpr std::uint32_t kFrequencySlew = 1U << 5;
  static constexpr std::uint32_t kAmplitudeSlew = 1U << 6;

  std::uint32_t fields = 0;
  Action action = Action::none;
  CommandSource source = CommandSource::internal;
  double frequency_hz = 0.0;
  double amplitude_vpp = 0.0;
  double phase_deg = 0.0;
  double load_n = 0.0;
  double frequency_slew_hz_per_s = 0.0;   // 0 = unlimited
  double amplitude_slew_vpp_per_s = 0.0;  // 0 = unlimited
  std::uint64_t sequence = 0;             // set by the transport (for latency measurement)
  std::uint64_t accepted_ns = 0;          // CLOCK_MONOTONIC receive time: Modbus when the transport
                                          // accepted it, CAN the bus's (kernel's) rx timestamp
};

struct AmplifierLimits {
  double min_frequency_hz = 30000.0;
  double max_frequency_hz = 50000.0;
  double max_amplitude_vpp = 600.0;
  double max_abs_phase_deg = 180.0;
  double max_abs_load_n = 30.0;
  double max_frequency_slew_hz_per_s = 1.0e7;
  double max_amplitude_slew_vpp_per_s = 1.0e7;
};

struct AmplifierConfig {
  AmplifierLimits limits;
  double tick_s = 1.0e-4;
  double watchdog_s = 0.1;  // 0 = no watchdog
  double frequency_hz = 40000.0;
  double amplitude_vpp = 0.0;
  double phase_deg = 90.0;
  double frequency_slew_hz_per_s = 1.0e6;   // 1 kHz/ms; 0 = unlimited
  double amplitude_slew_vpp_per_s = 1.0e5;  // 100 Vpp/ms; 0 = unlimited
};

// Static validation (ranges, codes): what every transport checks before queueing a command.
Reason validate(const Command& command, const AmplifierLimits& limits);

struct AmplifierSetpoints {
  double frequency_hz = 0.0;
  double amplitude_vpp = 0.0;
  double phase_deg = 0.0;
  double load_n = 0.0;
  double frequency_slew_hz_per_s = 0.0;
  double amplitude_slew_vpp_per_s = 0.0;
};

class Amplifier {
 public:
  explicit Amplifier(const AmplifierConfig& config);

  // Applies one command at the boundary of tick `tick`. Returns Reason::none when applied;
  // otherwise the command changed nothing.
  Reason apply(const Command& command, std::uint64_t tick);

  // Advances to tick `tick` (watchdog, enable line, slew) and returns the drive for it.
  DriveInput tick(std::uint64_t tick, bool enable_line);

  // Numerical blow-up etc.: drive off, fault latched until reset_fault.
  void raise_fault(FaultCode fault);

  [[nodiscard]] AmpState state() const { return state_; }
  [[nodiscard]] FaultCode fault() const { return fault_; }
  [[nodiscard]] const AmplifierSetpoints& setpoints() const { return setpoints_; }
  [[nodiscard]] const DriveInput& output() const { return output_; }
  [[nodiscard]] bool enable_line() const { return enable_line_; }
  [[nodiscard]] bool at_setpoint() const;
  [[nodiscard]] std::uint64_t applied_commands() const { return applied_; }
  [[nodiscard]] std::uint64_t rejected_commands() const { return rejected_; }
  [[nodiscard]] const AmplifierConfig& config() const { return config_; }

 private:
  AmplifierConfig config_;
  AmplifierSetpoints setpoints_;
  DriveInput output_{};
  AmpState state_ = AmpState::disabled;
  FaultCode fault_ = FaultCode::none;
  bool enable_line_ = true;
  std::uint64_t last_command_tick_ = 0;
  std::uint64_t watchdog_ticks_ = 0;
  std::uint64_t applied_ = 0;
  std::uint64_t rejected_ = 0;
};

}  // namespace swum::emu
