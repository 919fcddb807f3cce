// The host's walk of CiA 402 (host/device/cia402_master.h) against the emulated drive's state
// machine (firmware_sim/core/cia402_state.h): the controlword walks of enable, disable and fault
// reset, each word taken as the drive takes it, and the amplifier states of the other protocols.
// The codes both read and write (statusword coding, fault codes) are the shared codec's,
// canopen/cia402.h, tested in tests/canopen/cia402_test.cpp.
#include "device/cia402_master.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "cia402.h"
#include "core/cia402_state.h"

namespace swum::host::cia402 {
namespace {

// The states a walk passes, from `from`, taking each controlword as the drive does (transitions
// of emu::next_state), until the goal is reached or 8 words are sent.
std::vector<std::uint16_t> walk(Cia402State from, Goal goal, std::uint16_t last, Cia402State& end) {
  std::vector<std::uint16_t> words;
  Cia402State state = from;
  std::uint16_t previous = last;
  for (int i = 0; i < 8 && !reached(canopen::state_of(canopen::state_statusword(state)), goal); ++i) {
    const std::uint16_t word = next_controlword(canopen::state_of(canopen::state_statusword(state)), goal, previous);
    words.push_back(word);
    emu::Cia402Inputs in;
    in.command = canopen::decode_controlword(word);
    in.fault_reset_edge = (word & canopen::kControlwordFaultReset) != 0 &&
                          (previous & canopen::kControlwordFaultReset) == 0;
    state = emu::next_state(state, in).state;
    previous = word;
  }
  end = state;
  return words;
}

TEST(Cia402Master, EnableIsShutdownSwitchOnEnableOperation) {
  Cia402State end{};
  EXPECT_EQ(walk(Cia402State::switch_on_disabled, Goal::on, 0x00, end), (std::vector<std::uint16_t>{0x06, 0x07, 0x0F}));
  EXPECT_EQ(end, Cia402State::operation_enabled);
  EXPECT_EQ(walk(Cia402State::ready_to_switch_on, Goal::on, 0x06, end), (std::vector<std::uint16_t>{0x07, 0x0F}));
  EXPECT_TRUE(walk(Cia402State::operation_enabled, Goal::on, 0x0F, end).empty());
  // From quick stop active: enable operation (16).
  EXPECT_EQ(next_controlword(Cia402State::quick_stop_active, Goal::on, 0x02), 0x0F);
}

TEST(Cia402Master, DisableIsDisableOperationThenShutdown) {
  Cia402State end{};
  EXPECT_EQ(walk(Cia402State::operation_enabled, Goal::off, 0x0F, end), (std::vector<std::uint16_t>{0x07, 0x06}));
  EXPECT_EQ(end, Cia402State::ready_to_switch_on);
  EXPECT_EQ(walk(Cia402State::switch_on_disabled, Goal::off, 0x00, end), (std::vector<std::uint16_t>{0x06}));
  EXPECT_EQ(next_controlword(Cia402State::quick_stop_active, Goal::off, 0x02), 0x00);  // disable voltage (12)
}

TEST(Cia402Master, AFaultResetIsARisingEdgeOfBit7) {
  Cia402State end{};
  EXPECT_EQ(walk(Cia402State::fault, Goal::reset, 0x0F, end), (std::vector<std::uint16_t>{0x80, 0x06}));
  EXPECT_EQ(end, Cia402State::ready_to_switch_on);
  // The last word held bit 7 already: it is released first, or no edge would come.
  EXPECT_EQ(walk(Cia402State::fault, Goal::reset, 0x80, end), (std::vector<std::uint16_t>{0x00, 0x80, 0x06}));
  // No edge while the fault reaction runs (it would be spent there); enable and disable leave a fault alone.
  EXPECT_EQ(next_controlword(Cia402State::fault_reaction_active, Goal::reset, 0x0F), 0x00);
  EXPECT_EQ(next_controlword(Cia402State::fault, Goal::on, 0x0F), 0x00);
  EXPECT_EQ(next_controlword(Cia402State::fault, Goal::off, 0x0F), 0x00);
}

TEST(Cia402Master, NoGoalLeavesTheControlwordAlone) {
  for (const Cia402State s :
       {Cia402State::switch_on_disabled, Cia402State::operation_enabled, Cia402State::fault, Cia402State::unknown}) {
    EXPECT_TRUE(reached(s, Goal::none));
    EXPECT_EQ(next_controlword(s, Goal::none, 0x1234), 0x1234);
  }
  EXPECT_EQ(next_controlword(Cia402State::unknown, Goal::on, 0x0F), 0x00);
  EXPECT_EQ(next_controlword(Cia402State::not_ready_to_switch_on, Goal::on, 0x0F), 0x00);
}

TEST(Cia402Master, AmplifierStatesOfTheOtherProtocols) {
  EXPECT_EQ(amp_state(Cia402State::operation_enabled), protocol::AmpState::enabled);
  EXPECT_EQ(amp_state(Cia402State::quick_stop_active), protocol::AmpState::enabled);
  EXPECT_EQ(amp_state(Cia402State::fault_reaction_active), protocol::AmpState::fault);
  EXPECT_EQ(amp_state(Cia402State::fault), protocol::AmpState::fault);
  for (const Cia402State s : {Cia402State::not_ready_to_switch_on, Cia402State::switch_on_disabled,
                              Cia402State::ready_to_switch_on, Cia402State::switched_on, Cia402State::unknown})
    EXPECT_EQ(amp_state(s), protocol::AmpState::disabled);
}

}  // namespace
}  // namespace swum::host::cia402
