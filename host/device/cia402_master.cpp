#include "device/cia402_master.h"

namespace swum::host::cia402 {

using canopen::kControlwordDisableVoltage;
using canopen::kControlwordEnableOperation;
using canopen::kControlwordFaultReset;
using canopen::kControlwordShutdown;
using canopen::kControlwordSwitchOn;
using State = Cia402State;

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
      if (goal != Goal::reset) return kControlwordDisableVoltage;
      return (last & kControlwordFaultReset) != 0 ? kControlwordDisableVoltage : kControlwordFaultReset;
    case State::switch_on_disabled: return kControlwordShutdown;  // 2
    case State::ready_to_switch_on: return on ? kControlwordSwitchOn : kControlwordShutdown;
    case State::switched_on: return on ? kControlwordEnableOperation : kControlwordShutdown;              // 4 / 6
    case State::operation_enabled: return on ? kControlwordEnableOperation : kControlwordSwitchOn;        // - / 5
    case State::quick_stop_active: return on ? kControlwordEnableOperation : kControlwordDisableVoltage;  // 16 / 12
    case State::not_ready_to_switch_on:  // the drive passes to switch on disabled by itself (1)
    case State::fault_reaction_active:   // ... and to fault (14)
    case State::unknown: return kControlwordDisableVoltage;
  }
  return kControlwordDisableVoltage;
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

}  // namespace swum::host::cia402
