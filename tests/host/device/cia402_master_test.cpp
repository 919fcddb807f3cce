// The host's reading of CiA 402 (host/device/cia402_master.h) against CiA 402-2's tables and
// against the emulated drive's own writing of them (firmware_sim/core/cia402_state.h): every
// state's statusword read back as that state, the controlword walks of enable, disable and fault
// reset, and the swum faults' 0x603F codes mapped back to their fault codes.
#include "device/cia402_master.h"

#include <gtest/gtest.h>

#include "cia402.h"
#include "core/cia402_state.h"

namespace swum::host::cia402 {
namespace {

TEST(Cia402Master, ReadsEveryStateTheDriveWrites) {
  using emu::Cia402State;
  const std::pair<Cia402State, State> states[] = {
      {Cia402State::not_ready_to_switch_on, State::not_ready_to_switch_on},
      {Cia402State::switch_on_disabled, State::switch_on_disabled},
      {Cia402State::ready_to_switch_on, State::ready_to_switch_on},
      {Cia402State::switched_on, State::switched_on},
      {Cia402State::operation_enabled, State::operation_enabled},
      {Cia402State::quick_stop_active, State::quick_stop_active},
      {Cia402State::fault_reaction_active, State::fault_reaction_active},
      {Cia402State::fault, State::fault},
  };
  for (const auto& [drive, host] : states) {
    // With every flag the drive may add (warning, remote, target reached, internal limit, bits 12-13).
    for (const std::uint16_t flags : {0x0000, 0x0080, 0x0200, 0x0400, 0x0800, 0x1000, 0x2000, 0x3E80}) {
      const std::uint16_t word = static_cast<std::uint16_t>(canopen::state_statusword(drive) | flags);
      EXPECT_EQ(state_of(word), host) << canopen::to_string(drive) << " 0x" << std::hex << word;
    }
  }
}

TEST(Cia402Master, CodesOfCia402sTable) {
  // CiA 402-2 Table "state coding", bits 0-3, 5, 6, with don't-care bits set or clear.
  EXPECT_EQ(state_of(0x0000), State::not_ready_to_switch_on);
  EXPECT_EQ(state_of(0x0020), State::not_ready_to_switch_on);
  EXPECT_EQ(state_of(0x0040), State::switch_on_disabled);
  EXPECT_EQ(state_of(0x0060), State::switch_on_disabled);
  EXPECT_EQ(state_of(0x0021), State::ready_to_switch_on);
  EXPECT_EQ(state_of(0x0023), State::switched_on);
  EXPECT_EQ(state_of(0x0027), State::operation_enabled);
  EXPECT_EQ(state_of(0x0007), State::quick_stop_active);
  EXPECT_EQ(state_of(0x000F), State::fault_reaction_active);
  EXPECT_EQ(state_of(0x002F), State::fault_reaction_active);
  EXPECT_EQ(state_of(0x0008), State::fault);
  EXPECT_EQ(state_of(0x0028), State::fault);
  EXPECT_EQ(state_of(0x0001), State::unknown);  // ready to switch on without "quick stop" (bit 5)
  EXPECT_EQ(state_of(0x0041), State::unknown);
  EXPECT_STREQ(to_string(State::ready_to_switch_on), "ready to switch on");
}

// The states a walk passes, from `from`, taking each controlword as the drive does (transitions
// of emu::next_state), until the goal is reached or 8 words are sent.
std::vector<std::uint16_t> walk(emu::Cia402State from, Goal goal, std::uint16_t last, emu::Cia402State& end) {
  std::vector<std::uint16_t> words;
  emu::Cia402State state = from;
  std::uint16_t previous = last;
  for (int i = 0; i < 8 && !reached(state_of(canopen::state_statusword(state)), goal); ++i) {
    const std::uint16_t word = next_controlword(state_of(canopen::state_statusword(state)), goal, previous);
    words.push_back(word);
    emu::Cia402Inputs in;
    in.command = canopen::decode_controlword(word);
    in.fault_reset_edge = (word & 0x80) != 0 && (previous & 0x80) == 0;
    state = emu::next_state(state, in).state;
    previous = word;
  }
  end = state;
  return words;
}

TEST(Cia402Master, EnableIsShutdownSwitchOnEnableOperation) {
  emu::Cia402State end{};
  EXPECT_EQ(walk(emu::Cia402State::switch_on_disabled, Goal::on, 0x00, end),
            (std::vector<std::uint16_t>{0x06, 0x07, 0x0F}));
  EXPECT_EQ(end, emu::Cia402State::operation_enabled);
  EXPECT_EQ(walk(emu::Cia402State::ready_to_switch_on, Goal::on, 0x06, end), (std::vector<std::uint16_t>{0x07, 0x0F}));
  EXPECT_TRUE(walk(emu::Cia402State::operation_enabled, Goal::on, 0x0F, end).empty());
  // From quick stop active: enable operation (16).
  EXPECT_EQ(next_controlword(State::quick_stop_active, Goal::on, 0x02), 0x0F);
}

TEST(Cia402Master, DisableIsDisableOperationThenShutdown) {
  emu::Cia402State end{};
  EXPECT_EQ(walk(emu::Cia402State::operation_enabled, Goal::off, 0x0F, end), (std::vector<std::uint16_t>{0x07, 0x06}));
  EXPECT_EQ(end, emu::Cia402State::ready_to_switch_on);
  EXPECT_EQ(walk(emu::Cia402State::switch_on_disabled, Goal::off, 0x00, end), (std::vector<std::uint16_t>{0x06}));
  EXPECT_EQ(next_controlword(State::quick_stop_active, Goal::off, 0x02), 0x00);  // disable voltage (12)
}

TEST(Cia402Master, AFaultResetIsARisingEdgeOfBit7) {
  emu::Cia402State end{};
  EXPECT_EQ(walk(emu::Cia402State::fault, Goal::reset, 0x0F, end), (std::vector<std::uint16_t>{0x80, 0x06}));
  EXPECT_EQ(end, emu::Cia402State::ready_to_switch_on);
  // The last word held bit 7 already: it is released first, or no edge would come.
  EXPECT_EQ(walk(emu::Cia402State::fault, Goal::reset, 0x80, end), (std::vector<std::uint16_t>{0x00, 0x80, 0x06}));
  // No edge while the fault reaction runs (it would be spent there); enable and disable leave a fault alone.
  EXPECT_EQ(next_controlword(State::fault_reaction_active, Goal::reset, 0x0F), 0x00);
  EXPECT_EQ(next_controlword(State::fault, Goal::on, 0x0F), 0x00);
  EXPECT_EQ(next_controlword(State::fault, Goal::off, 0x0F), 0x00);
}

TEST(Cia402Master, NoGoalLeavesTheControlwordAlone) {
  for (const State s : {State::switch_on_disabled, State::operation_enabled, State::fault, State::unknown}) {
    EXPECT_TRUE(reached(s, Goal::none));
    EXPECT_EQ(next_controlword(s, Goal::none, 0x1234), 0x1234);
  }
  EXPECT_EQ(next_controlword(State::unknown, Goal::on, 0x0F), 0x00);
  EXPECT_EQ(next_controlword(State::not_ready_to_switch_on, Goal::on, 0x0F), 0x00);
}

TEST(Cia402Master, AmplifierStatesOfTheOtherProtocols) {
  EXPECT_EQ(amp_state(State::operation_enabled), protocol::AmpState::enabled);
  EXPECT_EQ(amp_state(State::quick_stop_active), protocol::AmpState::enabled);
  EXPECT_EQ(amp_state(State::fault_reaction_active), protocol::AmpState::fault);
  EXPECT_EQ(amp_state(State::fault), protocol::AmpState::fault);
  for (const State s : {State::not_ready_to_switch_on, State::switch_on_disabled, State::ready_to_switch_on,
                        State::switched_on, State::unknown})
    EXPECT_EQ(amp_state(s), protocol::AmpState::disabled);
}

TEST(Cia402Master, TheDrivesErrorCodesMapBackToSwumFaults) {
  using protocol::FaultCode;
  for (const FaultCode f : {FaultCode::none, FaultCode::command_timeout, FaultCode::numerical, FaultCode::over_current,
                            FaultCode::over_temperature}) {
    EXPECT_EQ(fault_code(canopen::error_code(f)), static_cast<int>(f)) << protocol::to_string(f);
  }
  EXPECT_EQ(fault_code(0x8130), 0x8130);  // the heartbeat error: no swum fault, kept as it is
  EXPECT_EQ(fault_code(0x1000), 0x1000);
}

}  // namespace
}  // namespace swum::host::cia402
