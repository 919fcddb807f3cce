// canopen/nmt.h: the NMT command frame decoded for this node, for all nodes and for others; every
// state × command transition of CiA 301's NMT state diagram (7.3.2); the boot-up and heartbeat
// frames byte for byte; what each state allows (Table 83).
#include "nmt.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>

#include "canopen_test_support.h"

namespace swum::canopen {
namespace {

using protocol::CanFrame;

using test::frame;

constexpr std::array kCommands{NmtCommand::start, NmtCommand::stop, NmtCommand::enter_pre_operational,
                               NmtCommand::reset_node, NmtCommand::reset_communication};

TEST(Nmt, DecodesEachCommandForThisNodeAndForAll) {
  for (const NmtCommand c : kCommands) {
    for (const std::uint8_t addressed : {std::uint8_t{5}, std::uint8_t{0}}) {
      NmtCommand got = NmtCommand::stop == c ? NmtCommand::start : NmtCommand::stop;
      EXPECT_EQ(decode_nmt(frame(0x000, {static_cast<std::uint8_t>(c), addressed}), 5, got), NmtDecode::for_us)
          << to_string(c) << " to node " << int(addressed);
      EXPECT_EQ(got, c);
    }
  }
}

TEST(Nmt, CommandsForOtherNodesAndOtherFramesAreNotForUs) {
  NmtCommand got = NmtCommand::stop;
  EXPECT_EQ(decode_nmt(frame(0x000, {0x01, 6}), 5, got), NmtDecode::not_for_us);
  EXPECT_EQ(decode_nmt(frame(0x000, {0x01, 127}), 5, got), NmtDecode::not_for_us);
  EXPECT_EQ(decode_nmt(frame(0x000, {0x01, 0x85}), 5, got), NmtDecode::not_for_us);
  EXPECT_EQ(decode_nmt(frame(0x001, {0x01, 5}), 5, got), NmtDecode::not_for_us);
  EXPECT_EQ(decode_nmt(frame(0x000, {0x01, 5}, true), 5, got), NmtDecode::not_for_us);  // 29-bit id 0
  EXPECT_EQ(got, NmtCommand::stop);                                                     // untouched
}

TEST(Nmt, WrongLengthsAndUnknownSpecifiersAreMalformed) {
  NmtCommand got = NmtCommand::stop;
  EXPECT_EQ(decode_nmt(frame(0x000, {}), 5, got), NmtDecode::malformed);
  EXPECT_EQ(decode_nmt(frame(0x000, {0x01}), 5, got), NmtDecode::malformed);
  EXPECT_EQ(decode_nmt(frame(0x000, {0x01, 5, 0}), 5, got), NmtDecode::malformed);
  EXPECT_EQ(decode_nmt(frame(0x000, {0x01, 5, 0, 0, 0, 0, 0, 0}), 5, got), NmtDecode::malformed);
  // Malformed whichever node it names: the frame is broken, not merely someone else's.
  EXPECT_EQ(decode_nmt(frame(0x000, {0x01, 6, 0}), 5, got), NmtDecode::malformed);
  for (const std::uint8_t cs : {0x00, 0x03, 0x7F, 0x83, 0xFF}) {
    EXPECT_EQ(decode_nmt(frame(0x000, {cs, 5}), 5, got), NmtDecode::malformed) << int(cs);
  }
  EXPECT_EQ(got, NmtCommand::stop);
}

TEST(Nmt, EveryStateAndCommand) {
  using S = NmtState;
  struct Row {
    S from;
    std::array<S, 5> to;  // start, stop, enter pre-op, reset node, reset communication
  };
  const std::array<Row, 4> table{{
      {S::initialising, {S::initialising, S::initialising, S::initialising, S::initialising, S::initialising}},
      {S::pre_operational, {S::operational, S::stopped, S::pre_operational, S::initialising, S::initialising}},
      {S::operational, {S::operational, S::stopped, S::pre_operational, S::initialising, S::initialising}},
      {S::stopped, {S::operational, S::stopped, S::pre_operational, S::initialising, S::initialising}},
  }};
  for (const Row& row : table) {
    for (std::size_t c = 0; c < kCommands.size(); ++c) {
      EXPECT_EQ(next_state(row.from, kCommands[c]), row.to[c])
          << to_string(row.from) << " + " << to_string(kCommands[c]) << " -> " << to_string(row.to[c]);
    }
  }
}

TEST(Nmt, BootUpAndHeartbeatFrames) {
  const CanFrame boot = boot_up_frame(5);
  EXPECT_EQ(boot.id, 0x705U);
  EXPECT_FALSE(boot.extended);
  EXPECT_EQ(boot.dlc, 1);
  EXPECT_EQ(boot.data[0], 0x00);
  const std::array<std::pair<NmtState, std::uint8_t>, 4> codes{{{NmtState::initialising, 0x00},
                                                                {NmtState::stopped, 0x04},
                                                                {NmtState::operational, 0x05},
                                                                {NmtState::pre_operational, 0x7F}}};
  for (const auto& [state, code] : codes) {
    const CanFrame hb = heartbeat_frame(127, state);
    EXPECT_EQ(hb.id, 0x77FU);
    EXPECT_EQ(hb.dlc, 1);
    EXPECT_EQ(hb.data[0], code) << to_string(state);
    for (std::size_t i = 1; i < 8; ++i) EXPECT_EQ(hb.data[i], 0);
  }
}

TEST(Nmt, NamesOfStates) {
  EXPECT_STREQ(to_string(NmtState::initialising), "initialising");
  EXPECT_STREQ(to_string(NmtState::stopped), "stopped");
  EXPECT_STREQ(to_string(NmtState::operational), "operational");
  EXPECT_STREQ(to_string(NmtState::pre_operational), "pre-operational");
  EXPECT_STREQ(to_string(static_cast<NmtState>(0x42)), "unknown");
}

TEST(Nmt, WhatEachStateAllows) {
  // Table 83: rows SDO, PDO, EMCY, SYNC; columns initialising, pre-operational, operational, stopped.
  const std::array states{NmtState::initialising, NmtState::pre_operational, NmtState::operational, NmtState::stopped};
  const std::array<std::array<bool, 4>, 4> allowed{{{false, true, true, false},
                                                    {false, false, true, false},
                                                    {false, true, true, false},
                                                    {false, true, true, false}}};
  for (std::size_t s = 0; s < states.size(); ++s) {
    EXPECT_EQ(sdo_allowed(states[s]), allowed[0][s]) << to_string(states[s]);
    EXPECT_EQ(pdo_allowed(states[s]), allowed[1][s]) << to_string(states[s]);
    EXPECT_EQ(emcy_allowed(states[s]), allowed[2][s]) << to_string(states[s]);
    EXPECT_EQ(sync_allowed(states[s]), allowed[3][s]) << to_string(states[s]);
  }
}

}  // namespace
}  // namespace swum::canopen
