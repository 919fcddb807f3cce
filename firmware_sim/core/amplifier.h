// The virtual two-phase amplifier: a pure state machine (no clock, no I/O, no allocation).
// Time is counted in loop ticks. Commands arrive from the transports through the command queue
// and are applied, in order, at the tick boundary; tick() then yields the drive input that the
// motor model integrates over the coming tick.
//
//   disabled --enable--> enabled --disable / enable line low--> disabled
//   enabled --watchdog timeout / numerical blow-up--> fault --reset_fault--> disabled
//
#pragma once

#include <cstdint>

#include "codes.h"
#include "command.h"
#include "model/motor_model.h"

namespace swum::emu {

// The codes, the command value and the limits are the protocol's (protocol/): the amplifier
// implements them.
using protocol::Action;
using protocol::AmplifierLimits;
using protocol::AmplifierSetpoints;
using protocol::AmpState;
using protocol::Command;
using protocol::CommandSource;
using protocol::FaultCode;
using protocol::kMaxAction;
using protocol::Reason;
using protocol::to_string;
using protocol::validate;

struct AmplifierConfig {
  AmplifierLimits limits;
  double tick_s = 1.0e-4;
  double watchdog_s = 0.1;  // 0 = no watchdog
  double frequency_hz = 40000.0;
  double amplitude_v = 0.0;
  double phase_deg = 90.0;
  double frequency_slew_hz_per_s = 1.0e6;  // 1 kHz/ms; 0 = unlimited
  double amplitude_slew_v_per_s = 1.0e5;   // 100 V/ms; 0 = unlimited
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
