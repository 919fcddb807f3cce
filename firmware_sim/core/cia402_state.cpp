#include "core/cia402_state.h"

namespace swum::emu {

bool quick_stop_option_supported(std::int16_t option) {
  return option == 0 || option == 1 || option == 2 || option == 5 || option == 6;
}

QuickStopBehaviour quick_stop_behaviour(std::int16_t option) {
  switch (option) {
    case 0: return {QuickStopRamp::none, false};
    case 1: return {QuickStopRamp::profile_deceleration, false};
    case 5: return {QuickStopRamp::profile_deceleration, true};
    case 6: return {QuickStopRamp::quick_stop_deceleration, true};
    default: return {QuickStopRamp::quick_stop_deceleration, false};  // 2, and what is not supported
  }
}

namespace {

Cia402Step go(Cia402State to, std::int8_t first, std::int8_t second = kNoTransition) { return {to, {first, second}}; }

}  // namespace

Cia402Step next_state(Cia402State state, const Cia402Inputs& in) {
  using S = Cia402State;
  using C = Cia402Command;
  const Cia402Step stay{state, {kNoTransition, kNoTransition}};
  switch (state) {
    case S::fault_reaction_active: return go(S::fault, 14);
    case S::fault: return in.fault_reset_edge && !in.fault ? go(S::switch_on_disabled, 15) : stay;
    default: break;
  }
  if (in.fault) return go(S::fault_reaction_active, 13);
  switch (state) {
    case S::not_ready_to_switch_on: return go(S::switch_on_disabled, 1);
    case S::switch_on_disabled: return in.command == C::shutdown ? go(S::ready_to_switch_on, 2) : stay;
    case S::ready_to_switch_on:
      switch (in.command) {
        case C::switch_on: return go(S::switched_on, 3);
        case C::enable_operation: return go(S::operation_enabled, 3, 4);
        case C::disable_voltage:
        case C::quick_stop: return go(S::switch_on_disabled, 7);
        default: return stay;
      }
    case S::switched_on:
      switch (in.command) {
        case C::shutdown: return go(S::ready_to_switch_on, 6);
        case C::enable_operation: return go(S::operation_enabled, 4);
        case C::disable_voltage:
        case C::quick_stop: return go(S::switch_on_disabled, 10);
        default: return stay;
      }
    case S::operation_enabled:
      switch (in.command) {
        case C::switch_on: return go(S::switched_on, 5);  // "disable operation"
        case C::shutdown: return go(S::ready_to_switch_on, 8);
        case C::disable_voltage: return go(S::switch_on_disabled, 9);
        case C::quick_stop:
          // Option 0 disables the drive function at once: through quick stop active, not in it.
          if (quick_stop_behaviour(in.quick_stop_option).ramp == QuickStopRamp::none)
            return go(S::switch_on_disabled, 11, 12);
          return go(S::quick_stop_active, 11);
        default: return stay;
      }
    case S::quick_stop_active: {
      const QuickStopBehaviour b = quick_stop_behaviour(in.quick_stop_option);
      if (in.command == C::disable_voltage) return go(S::switch_on_disabled, 12);
      if (!b.stays_in_quick_stop_active && (in.quick_stop_finished || b.ramp == QuickStopRamp::none))
        return go(S::switch_on_disabled, 12);
      if (b.stays_in_quick_stop_active && in.command == C::enable_operation && !in.enable_operation_is_stale)
        return go(S::operation_enabled, 16);
      return stay;
    }
    default: return stay;
  }
}

std::uint16_t statusword(Cia402State state, const Cia402StatusFlags& f) {
  std::uint16_t word = canopen::state_statusword(state);
  if (f.warning) word |= canopen::kStatuswordWarning;
  if (f.target_reached) word |= canopen::kStatuswordTargetReached;
  if (f.internal_limit) word |= canopen::kStatuswordInternalLimit;
  if (f.mode_bit12) word |= canopen::kStatuswordModeBit12;
  if (f.mode_bit13) word |= canopen::kStatuswordModeBit13;
  return word;
}

}  // namespace swum::emu
