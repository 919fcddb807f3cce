#include "device/cia402_master.h"

namespace swum::host::cia402 {

namespace {

// CiA 402-2 Table "state coding": the bits that select each state and their values (bit 5,
// quick stop, only where it tells two states apart).
struct Coding {
  std::uint16_t mask;
  std::uint16_t value;
  State state;
};
constexpr Coding kCodings[] = {
    {0x4F, 0x00, State::not_ready_to_switch_on}, {0x4F, 0x40, State::switch_on_disabled},
    {0x6F, 0x21, State::ready_to_switch_on},     {0x6F, 0x23, State::switched_on},
    {0x6F, 0x27, State::operation_enabled},      {0x6F, 0x07, State::quick_stop_active},
    {0x4F, 0x0F, State::fault_reaction_active},  {0x4F, 0x08, State::fault},
};

constexpr std::uint16_t kFaultResetBit = 0x80;

}  // namespace

State state_of(std::uint16_t statusword) {
  for (const Coding& c : kCodings)
    if ((statusword & c.mask) == c.value) return c.state;
  return State::unknown;
}

const char* to_string(State state) {
  switch (state) {
    case State::not_ready_to_switch_on: return "not ready to switch on";
    case State::switch_on_disabled: return "switch on disabled";
    case State::ready_to_switch_on: return "ready to switch on";
    case State::switched_on: return "switched on";
    case State::operation_enabled: return "operation enabled";
    case State::quick_stop_active: return "quick stop active";
    case State::fault_reaction_active: return "fault reaction active";
    case State::fault: return "fault";
    case State::unknown: return "no CiA 402 state";
  }
  return "?";
}

bool reached(State state, Goal goal) {
  switch (goal) {
    case Goal::none: return true;
    case Goal::on: return state == State::operation_enabled;
    case Goal::off:
    case Goal::reset: return state == State::ready_to_switch_on;
  }
  return false;
}

std::uint16_t next_controlword(State state, Goal goal, std::uint16_t last) {
  if (goal == Goal::none || reached(state, goal)) return last;
  const bool on = goal == Goal::on;
  switch (state) {
    case State::fault:
      // Only the reset's rising edge leaves fault (transition 15); make one, from a word without bit 7.
      if (goal != Goal::reset) return kDisableVoltage;
      return (last & kFaultResetBit) != 0 ? kDisableVoltage : kFaultReset;
    case State::switch_on_disabled: return kShutdown;  // 2
    case State::ready_to_switch_on: return on ? kSwitchOn : kShutdown;
    case State::switched_on: return on ? kEnableOperation : kShutdown;              // 4 / 6
    case State::operation_enabled: return on ? kEnableOperation : kSwitchOn;        // - / 5
    case State::quick_stop_active: return on ? kEnableOperation : kDisableVoltage;  // 16 / 12
    case State::not_ready_to_switch_on:  // the drive passes to switch on disabled by itself (1)
    case State::fault_reaction_active:   // ... and to fault (14)
    case State::unknown: return kDisableVoltage;
  }
  return kDisableVoltage;
}

protocol::AmpState amp_state(State state) {
  switch (state) {
    case State::operation_enabled:
    case State::quick_stop_active: return protocol::AmpState::enabled;
    case State::fault_reaction_active:
    case State::fault: return protocol::AmpState::fault;
    default: return protocol::AmpState::disabled;
  }
}

int fault_code(std::uint16_t error_code) {
  using protocol::FaultCode;
  switch (error_code) {
    case 0x0000: return static_cast<int>(FaultCode::none);
    case 0x4310: return static_cast<int>(FaultCode::over_temperature);  // excess temperature drive
    case 0x2320: return static_cast<int>(FaultCode::over_current);      // short circuit, output side
    case 0x6100: return static_cast<int>(FaultCode::numerical);         // internal software
    case 0x8100: return static_cast<int>(FaultCode::command_timeout);   // communication
    default: return error_code;
  }
}

}  // namespace swum::host::cia402
