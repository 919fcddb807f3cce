#include "core/cia402_state.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace swum::emu {
namespace {

using C = Cia402Command;
using S = Cia402State;

struct Row {
  S from;
  C command;
  S to;
  std::int8_t first;
  std::int8_t second;
};

Cia402Step step(S from, C command, std::int16_t quick_stop_option = 2) {
  Cia402Inputs in;
  in.command = command;
  in.quick_stop_option = quick_stop_option;
  return next_state(from, in);
}

// Every state that takes commands against every command (CiA 402-2 Figure "state machine"):
// the transitions 2-12 and 16 by their numbers, and no transition where the figure has none.
TEST(Cia402StateMachine, EveryCommandInEveryStateTakesTheTransitionOfTheFigure) {
  constexpr std::int8_t n = kNoTransition;
  const std::vector<Row> rows = {
      {S::switch_on_disabled, C::none, S::switch_on_disabled, n, n},
      {S::switch_on_disabled, C::shutdown, S::ready_to_switch_on, 2, n},
      {S::switch_on_disabled, C::switch_on, S::switch_on_disabled, n, n},
      {S::switch_on_disabled, C::enable_operation, S::switch_on_disabled, n, n},  // 0x0F needs 0x06 first
      {S::switch_on_disabled, C::disable_voltage, S::switch_on_disabled, n, n},
      {S::switch_on_disabled, C::quick_stop, S::switch_on_disabled, n, n},
      {S::ready_to_switch_on, C::none, S::ready_to_switch_on, n, n},
      {S::ready_to_switch_on, C::shutdown, S::ready_to_switch_on, n, n},
      {S::ready_to_switch_on, C::switch_on, S::switched_on, 3, n},
      {S::ready_to_switch_on, C::enable_operation, S::operation_enabled, 3, 4},  // "switch on + enable operation"
      {S::ready_to_switch_on, C::disable_voltage, S::switch_on_disabled, 7, n},
      {S::ready_to_switch_on, C::quick_stop, S::switch_on_disabled, 7, n},
      {S::switched_on, C::none, S::switched_on, n, n},
      {S::switched_on, C::shutdown, S::ready_to_switch_on, 6, n},
      {S::switched_on, C::switch_on, S::switched_on, n, n},
      {S::switched_on, C::enable_operation, S::operation_enabled, 4, n},
      {S::switched_on, C::disable_voltage, S::switch_on_disabled, 10, n},
      {S::switched_on, C::quick_stop, S::switch_on_disabled, 10, n},
      {S::operation_enabled, C::none, S::operation_enabled, n, n},
      {S::operation_enabled, C::shutdown, S::ready_to_switch_on, 8, n},
      {S::operation_enabled, C::switch_on, S::switched_on, 5, n},  // "disable operation"
      {S::operation_enabled, C::enable_operation, S::operation_enabled, n, n},
      {S::operation_enabled, C::disable_voltage, S::switch_on_disabled, 9, n},
      {S::operation_enabled, C::quick_stop, S::quick_stop_active, 11, n},
      {S::quick_stop_active, C::none, S::quick_stop_active, n, n},
      {S::quick_stop_active, C::shutdown, S::quick_stop_active, n, n},
      {S::quick_stop_active, C::switch_on, S::quick_stop_active, n, n},
      {S::quick_stop_active, C::enable_operation, S::quick_stop_active, n, n},  // option 2: no 16
      {S::quick_stop_active, C::disable_voltage, S::switch_on_disabled, 12, n},
      {S::quick_stop_active, C::quick_stop, S::quick_stop_active, n, n},
  };
  for (const Row& r : rows) {
    const Cia402Step s = step(r.from, r.command);
    EXPECT_EQ(s.state, r.to) << to_string(r.from) << " + command " << static_cast<int>(r.command);
    EXPECT_EQ(s.transitions[0], r.first) << to_string(r.from) << " + command " << static_cast<int>(r.command);
    EXPECT_EQ(s.transitions[1], r.second) << to_string(r.from) << " + command " << static_cast<int>(r.command);
    EXPECT_EQ(s.changed(), r.first != kNoTransition);
  }
}

TEST(Cia402StateMachine, StartsThroughNotReadyToSwitchOnWhateverTheCommand) {
  for (C command : {C::none, C::shutdown, C::enable_operation}) {
    const Cia402Step s = step(S::not_ready_to_switch_on, command);
    EXPECT_EQ(s.state, S::switch_on_disabled);
    EXPECT_EQ(s.transitions[0], 1);
  }
}

TEST(Cia402StateMachine, AFaultReachesFaultThroughTheReactionFromEveryState) {
  for (S from : {S::not_ready_to_switch_on, S::switch_on_disabled, S::ready_to_switch_on, S::switched_on,
                 S::operation_enabled, S::quick_stop_active}) {
    Cia402Inputs in;
    in.command = C::enable_operation;
    in.fault = true;
    const Cia402Step reaction = next_state(from, in);
    EXPECT_EQ(reaction.state, S::fault_reaction_active) << to_string(from);
    EXPECT_EQ(reaction.transitions[0], 13);
    const Cia402Step done = next_state(reaction.state, in);  // the reaction takes one step, fault or not
    EXPECT_EQ(done.state, S::fault);
    EXPECT_EQ(done.transitions[0], 14);
  }
}

TEST(Cia402StateMachine, FaultResetActsOnlyOnTheEdgeAndOnlyWhenTheFaultIsGone) {
  Cia402Inputs held;  // bit 7 held (no command), no new edge
  held.command = C::none;
  EXPECT_EQ(next_state(S::fault, held).state, S::fault);
  Cia402Inputs command_without_edge;
  command_without_edge.command = C::shutdown;
  EXPECT_EQ(next_state(S::fault, command_without_edge).state, S::fault);
  Cia402Inputs edge_fault_still_there;
  edge_fault_still_there.fault_reset_edge = true;
  edge_fault_still_there.fault = true;
  EXPECT_EQ(next_state(S::fault, edge_fault_still_there).state, S::fault);
  Cia402Inputs edge;
  edge.fault_reset_edge = true;
  const Cia402Step reset = next_state(S::fault, edge);
  EXPECT_EQ(reset.state, S::switch_on_disabled);
  EXPECT_EQ(reset.transitions[0], 15);
  // An edge outside fault is no command.
  for (S from : {S::switch_on_disabled, S::ready_to_switch_on, S::switched_on, S::operation_enabled}) {
    EXPECT_EQ(next_state(from, edge).state, from) << to_string(from);
  }
}

TEST(Cia402QuickStop, OptionsSelectTheRampAndWhereTheDriveEnds) {
  struct Expected {
    std::int16_t option;
    QuickStopRamp ramp;
    bool stays;
    bool supported;
  };
  const std::vector<Expected> table = {
      {0, QuickStopRamp::none, false, true},
      {1, QuickStopRamp::profile_deceleration, false, true},
      {2, QuickStopRamp::quick_stop_deceleration, false, true},
      {5, QuickStopRamp::profile_deceleration, true, true},
      {6, QuickStopRamp::quick_stop_deceleration, true, true},
      // Current and voltage limit options, manufacturer and reserved values: as 2.
      {3, QuickStopRamp::quick_stop_deceleration, false, false},
      {4, QuickStopRamp::quick_stop_deceleration, false, false},
      {7, QuickStopRamp::quick_stop_deceleration, false, false},
      {8, QuickStopRamp::quick_stop_deceleration, false, false},
      {-1, QuickStopRamp::quick_stop_deceleration, false, false},
      {32767, QuickStopRamp::quick_stop_deceleration, false, false},
  };
  for (const Expected& e : table) {
    const QuickStopBehaviour b = quick_stop_behaviour(e.option);
    EXPECT_EQ(b.ramp, e.ramp) << e.option;
    EXPECT_EQ(b.stays_in_quick_stop_active, e.stays) << e.option;
    EXPECT_EQ(quick_stop_option_supported(e.option), e.supported) << e.option;
  }
}

TEST(Cia402QuickStop, Option0DisablesAtOnceThroughQuickStopActive) {
  const Cia402Step s = step(S::operation_enabled, C::quick_stop, 0);
  EXPECT_EQ(s.state, S::switch_on_disabled);
  EXPECT_EQ(s.transitions[0], 11);
  EXPECT_EQ(s.transitions[1], 12);
}

TEST(Cia402QuickStop, Options1And2LeaveForSwitchOnDisabledOnlyWhenTheRampIsDone) {
  for (std::int16_t option : {1, 2}) {
    Cia402Inputs in;
    in.command = C::quick_stop;
    in.quick_stop_option = option;
    EXPECT_EQ(next_state(S::quick_stop_active, in).state, S::quick_stop_active) << option;
    in.quick_stop_finished = true;
    const Cia402Step done = next_state(S::quick_stop_active, in);
    EXPECT_EQ(done.state, S::switch_on_disabled) << option;
    EXPECT_EQ(done.transitions[0], 12);
    in.command = C::enable_operation;  // no way back to operation enabled
    in.quick_stop_finished = false;
    EXPECT_EQ(next_state(S::quick_stop_active, in).state, S::quick_stop_active) << option;
  }
}

TEST(Cia402QuickStop, Options5And6StayUntilEnableOperationThatIsNotStale) {
  for (std::int16_t option : {5, 6}) {
    Cia402Inputs in;
    in.command = C::quick_stop;
    in.quick_stop_option = option;
    in.quick_stop_finished = true;
    EXPECT_EQ(next_state(S::quick_stop_active, in).state, S::quick_stop_active) << option;
    in.command = C::enable_operation;
    in.enable_operation_is_stale = true;  // the device stopped by itself: the latched 0x0F is no new command
    EXPECT_EQ(next_state(S::quick_stop_active, in).state, S::quick_stop_active) << option;
    in.enable_operation_is_stale = false;
    const Cia402Step back = next_state(S::quick_stop_active, in);
    EXPECT_EQ(back.state, S::operation_enabled) << option;
    EXPECT_EQ(back.transitions[0], 16);
    in.command = C::disable_voltage;
    EXPECT_EQ(next_state(S::quick_stop_active, in).state, S::switch_on_disabled) << option;
  }
}

// The drive's statusword without flags is the codec's word of its state (canopen/cia402.h,
// tested in tests/canopen/cia402_test.cpp).
TEST(Cia402Statusword, WithoutFlagsIsTheStatesWord) {
  const std::vector<std::pair<S, std::uint16_t>> words = {
      {S::not_ready_to_switch_on, 0x0200}, {S::switch_on_disabled, 0x0240},
      {S::ready_to_switch_on, 0x0231},     {S::switched_on, 0x0233},
      {S::operation_enabled, 0x0237},      {S::quick_stop_active, 0x0217},
      {S::fault_reaction_active, 0x020F},  {S::fault, 0x0208},
  };
  for (const auto& [state, word] : words) EXPECT_EQ(statusword(state, {}), word) << to_string(state);
}

TEST(Cia402Statusword, FlagsSetTheirBits) {
  const S op = S::operation_enabled;
  EXPECT_EQ(statusword(op, {.warning = true}), 0x02B7);
  EXPECT_EQ(statusword(op, {.target_reached = true}), 0x0637);
  EXPECT_EQ(statusword(op, {.internal_limit = true}), 0x0A37);
  EXPECT_EQ(statusword(op, {.mode_bit12 = true}), 0x1237);
  EXPECT_EQ(statusword(op, {.mode_bit13 = true}), 0x2237);
  EXPECT_EQ(statusword(S::fault, {.warning = true, .target_reached = true}), 0x0688);
}

}  // namespace
}  // namespace swum::emu
