// canopen/heartbeat.h: the producer's timing (first heartbeat one period after the boot-up, a
// period change, a stall gives one late frame and no burst, 0 disables) and the consumer's
// (monitoring from the first heartbeat, each loss reported once, recovery, reconfiguration), and
// the duplicate check of 0x1016 (CiA 301 7.5.2.19).
#include "heartbeat.h"

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "canopen_test_support.h"

namespace swum::canopen {
namespace {

constexpr std::int64_t kMs = 1'000'000;

using test::Frames;

// The times (ms) at which a producer polled every `step_ms` up to `end_ms` sends.
std::vector<std::int64_t> heartbeat_times(HeartbeatProducer& p, std::int64_t from_ms, std::int64_t end_ms,
                                          std::int64_t step_ms, Frames& out) {
  std::vector<std::int64_t> times;
  for (std::int64_t t = from_ms; t <= end_ms; t += step_ms) {
    const std::size_t before = out.sent.size();
    p.poll(t * kMs, 3, NmtState::operational, out);
    if (out.sent.size() != before) times.push_back(t);
  }
  return times;
}

TEST(HeartbeatProducer, FirstOnePeriodAfterTheBootUpThenEveryPeriod) {
  HeartbeatProducer p;
  p.configure(100);
  p.restart(1000 * kMs);  // the boot-up was sent at 1000 ms
  Frames out;
  EXPECT_EQ(heartbeat_times(p, 1000, 1350, 1, out), (std::vector<std::int64_t>{1100, 1200, 1300}));
  ASSERT_EQ(out.sent.size(), 3U);
  EXPECT_EQ(out.sent[0].id, 0x703U);
  EXPECT_EQ(out.sent[0].dlc, 1);
  EXPECT_EQ(out.sent[0].data[0], 0x05);
}

TEST(HeartbeatProducer, CarriesTheStateOfTheCall) {
  HeartbeatProducer p;
  p.configure(10);
  p.restart(0);
  Frames out;
  p.poll(10 * kMs, 9, NmtState::pre_operational, out);
  p.poll(20 * kMs, 9, NmtState::stopped, out);
  ASSERT_EQ(out.sent.size(), 2U);
  EXPECT_EQ(out.sent[0].data[0], 0x7F);
  EXPECT_EQ(out.sent[1].data[0], 0x04);
  EXPECT_EQ(out.sent[1].id, 0x709U);
}

TEST(HeartbeatProducer, KeepsItsGridWhenPolledLate) {
  HeartbeatProducer p;
  p.configure(100);
  p.restart(0);
  Frames out;
  // Polled every 30 ms: each heartbeat at the first poll at or after k * 100 ms, no drift.
  EXPECT_EQ(heartbeat_times(p, 0, 600, 30, out), (std::vector<std::int64_t>{120, 210, 300, 420, 510, 600}));
}

TEST(HeartbeatProducer, AStallGivesOneLateFrameAndNoBurst) {
  HeartbeatProducer p;
  p.configure(100);
  p.restart(0);
  Frames out;
  EXPECT_EQ(heartbeat_times(p, 0, 100, 10, out), (std::vector<std::int64_t>{100}));
  // Nothing polled from 100 to 750 ms (a stalled thread): one heartbeat at 750, the next at 850.
  EXPECT_EQ(heartbeat_times(p, 750, 960, 10, out), (std::vector<std::int64_t>{750, 850, 950}));
}

TEST(HeartbeatProducer, ZeroDisablesAndAChangeCountsFromTheLastHeartbeat) {
  HeartbeatProducer p;
  p.configure(0);
  p.restart(0);
  Frames out;
  EXPECT_TRUE(heartbeat_times(p, 0, 5000, 100, out).empty());
  p.configure(1000);  // 0x1017 written at 5000 ms: counted from the boot-up at 0, so due at once
  EXPECT_EQ(heartbeat_times(p, 5000, 7000, 100, out), (std::vector<std::int64_t>{5000, 6000, 7000}));
  p.configure(200);  // at 7000 ms, just after the heartbeat of 7000
  EXPECT_EQ(heartbeat_times(p, 7100, 7600, 100, out), (std::vector<std::int64_t>{7200, 7400, 7600}));
}

protocol::CanFrame heartbeat_of(std::uint8_t node, std::uint8_t state = 0x05, std::uint8_t dlc = 1) {
  protocol::CanFrame f;
  f.id = 0x700U + node;
  f.dlc = dlc;
  f.data[0] = state;
  return f;
}

constexpr std::uint32_t entry(std::uint8_t node, std::uint16_t ms) { return (std::uint32_t{node} << 16) | ms; }

TEST(HeartbeatConsumer, WatchesOnlyAfterTheFirstHeartbeat) {
  HeartbeatConsumer c;
  const std::array<std::uint32_t, 4> entries{entry(7, 100), 0, 0, 0};
  c.configure(entries);
  EXPECT_EQ(c.poll(10'000 * kMs), 0);  // node 7 never heard: not lost (CiA 301: monitoring starts at the first)
  c.on_frame(heartbeat_of(7), 10'000 * kMs);
  EXPECT_EQ(c.poll(10'100 * kMs), 0);  // exactly the time: not yet
  EXPECT_EQ(c.poll(10'101 * kMs), 7);
  EXPECT_EQ(c.poll(10'200 * kMs), 0);  // reported once
  EXPECT_EQ(c.poll(20'000 * kMs), 0);
}

TEST(HeartbeatConsumer, RecoversWhenTheNodeIsHeardAgainAndLosesItAgain) {
  HeartbeatConsumer c;
  const std::array<std::uint32_t, 4> entries{0, entry(7, 100), 0, 0};
  c.configure(entries);
  c.on_frame(heartbeat_of(7), 0);
  for (std::int64_t t = 50; t <= 1000; t += 50) {  // heartbeats every 50 ms: never lost
    c.on_frame(heartbeat_of(7), t * kMs);
    EXPECT_EQ(c.poll(t * kMs + 1), 0);
  }
  EXPECT_EQ(c.poll(1200 * kMs), 7);
  c.on_frame(heartbeat_of(7, 0x7F), 1300 * kMs);
  EXPECT_EQ(c.last_state(1), 0x7F);
  EXPECT_EQ(c.poll(1350 * kMs), 0);
  EXPECT_EQ(c.poll(1401 * kMs), 7);
}

TEST(HeartbeatConsumer, SeveralLossesOneNodePerCall) {
  HeartbeatConsumer c;
  const std::array<std::uint32_t, 4> entries{entry(2, 100), entry(3, 200), entry(4, 100), entry(0, 100)};
  c.configure(entries);
  for (const std::uint8_t n : {2, 3, 4}) c.on_frame(heartbeat_of(n), 0);
  c.on_frame(heartbeat_of(4), 90 * kMs);
  EXPECT_EQ(c.poll(150 * kMs), 2);
  EXPECT_EQ(c.poll(150 * kMs), 0);
  EXPECT_EQ(c.poll(191 * kMs), 4);
  EXPECT_EQ(c.poll(250 * kMs), 3);
  EXPECT_EQ(c.poll(250 * kMs), 0);
}

TEST(HeartbeatConsumer, IgnoresOtherFramesAndUnwatchedNodes) {
  HeartbeatConsumer c;
  const std::array<std::uint32_t, 4> entries{entry(7, 100), entry(8, 0), 0, 0};
  c.configure(entries);
  c.on_frame(heartbeat_of(7, 0x05, 0), 0);  // no data: not a heartbeat
  c.on_frame(heartbeat_of(7, 0x05, 2), 0);
  protocol::CanFrame extended = heartbeat_of(7);
  extended.extended = true;
  c.on_frame(extended, 0);
  c.on_frame(heartbeat_of(8), 0);  // time 0: unused
  EXPECT_EQ(c.poll(1000 * kMs), 0);
}

TEST(HeartbeatConsumer, AChangedEntryStartsOverAnUnchangedOneKeepsWatching) {
  HeartbeatConsumer c;
  std::array<std::uint32_t, 4> entries{entry(7, 100), entry(9, 100), 0, 0};
  c.configure(entries);
  c.on_frame(heartbeat_of(7), 0);
  c.on_frame(heartbeat_of(9), 0);
  entries[1] = entry(9, 500);  // the master writes sub 2 at 50 ms
  c.configure(entries);
  EXPECT_EQ(c.poll(150 * kMs), 7);
  EXPECT_EQ(c.poll(10'000 * kMs), 0);  // node 9 waits for its next heartbeat
  c.on_frame(heartbeat_of(9), 10'000 * kMs);
  EXPECT_EQ(c.poll(10'400 * kMs), 0);
  EXPECT_EQ(c.poll(10'501 * kMs), 9);
}

TEST(HeartbeatConsumer, BootUpCountsAsHeard) {
  HeartbeatConsumer c;
  const std::array<std::uint32_t, 4> entries{entry(7, 100), 0, 0, 0};
  c.configure(entries);
  c.on_frame(heartbeat_of(7, 0x00), 0);
  EXPECT_EQ(c.last_state(0), 0x00);
  EXPECT_EQ(c.poll(101 * kMs), 7);
}

TEST(ConsumerEntryCheck, RefusesASecondEntryForTheSameNode) {
  const std::array<std::uint32_t, 4> entries{entry(7, 100), entry(8, 100), 0, entry(9, 0)};
  EXPECT_EQ(check_consumer_entry(entries, 2, entry(7, 300)), SdoAbort::general_incompatibility);
  EXPECT_EQ(check_consumer_entry(entries, 2, entry(8, 1)), SdoAbort::general_incompatibility);
  EXPECT_EQ(static_cast<std::uint32_t>(SdoAbort::general_incompatibility), 0x06040043U);
  // The entry itself may be rewritten; an entry with time 0 is unused; a new node is fine.
  EXPECT_EQ(check_consumer_entry(entries, 0, entry(7, 300)), SdoAbort::none);
  EXPECT_EQ(check_consumer_entry(entries, 2, entry(9, 100)), SdoAbort::none);
  EXPECT_EQ(check_consumer_entry(entries, 2, entry(10, 100)), SdoAbort::none);
  // Unused entries never collide: time 0 or node 0.
  EXPECT_EQ(check_consumer_entry(entries, 2, entry(7, 0)), SdoAbort::none);
  EXPECT_EQ(check_consumer_entry(entries, 2, entry(0, 100)), SdoAbort::none);
}

TEST(ConsumerEntryCheck, RefusesReservedBitsAndNodesAbove127) {
  const std::array<std::uint32_t, 4> entries{};
  EXPECT_EQ(check_consumer_entry(entries, 0, entry(128, 100)), SdoAbort::value_range);
  EXPECT_EQ(check_consumer_entry(entries, 0, 0x01070064U), SdoAbort::value_range);
  EXPECT_EQ(check_consumer_entry(entries, 0, 0x01000000U), SdoAbort::value_range);  // even when unused
  EXPECT_EQ(check_consumer_entry(entries, 0, entry(127, 100)), SdoAbort::none);
}

}  // namespace
}  // namespace swum::canopen
