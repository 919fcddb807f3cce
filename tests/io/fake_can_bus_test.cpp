// The fake CAN bus obeys the CanBus contract (the same the vcan tests check on SocketCanBus).
#include <gtest/gtest.h>
#include <linux/can/error.h>

#include <thread>

#include "fake_can_bus.h"

using namespace swum::io;
using namespace std::chrono_literals;

namespace {
CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes, bool ext = false) {
  CanFrame f;
  f.id = id;
  f.extended = ext;
  f.dlc = static_cast<std::uint8_t>(bytes.size());
  std::copy(bytes.begin(), bytes.end(), f.data.begin());
  return f;
}
std::chrono::nanoseconds now_realtime() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch());
}
}  // namespace

TEST(FakeCanBus, DeliversToOthersNotToSenderWithTimestamp) {
  auto net = FakeCanNetwork::create();
  auto a = net->attach("a");
  auto b = net->attach("b");
  const auto before = now_realtime();
  ASSERT_TRUE(a->send(frame(0x123, {0xDE, 0xAD, 0xBE, 0xEF})).ok());
  CanFrame got;
  auto r = b->receive(got, 1000ms);
  ASSERT_EQ(r.status, CanStatus::ok) << r.message;
  EXPECT_TRUE(same_content(got, frame(0x123, {0xDE, 0xAD, 0xBE, 0xEF})));
  EXPECT_GE(got.timestamp, before);
  EXPECT_LE(got.timestamp, now_realtime());
  EXPECT_EQ(a->receive(got, 10ms).status, CanStatus::timeout);
}

TEST(FakeCanBus, ReceiveTimesOutWithMessage) {
  auto net = FakeCanNetwork::create();
  auto a = net->attach("a");
  CanFrame got;
  const auto t0 = std::chrono::steady_clock::now();
  auto r = a->receive(got, 30ms);
  EXPECT_EQ(r.status, CanStatus::timeout);
  EXPECT_GE(std::chrono::steady_clock::now() - t0, 30ms);
  EXPECT_NE(r.message.find("within 30 ms"), std::string::npos) << r.message;
}

TEST(FakeCanBus, InvalidFramesAreRefused) {
  auto net = FakeCanNetwork::create();
  auto a = net->attach();
  auto r = a->send(frame(0x800, {}));
  EXPECT_EQ(r.status, CanStatus::error);
  EXPECT_NE(r.message.find("0x800"), std::string::npos);
  EXPECT_EQ(a->set_filters(std::vector<CanFilter>{{0x900, 0x7FF, false}}).status, CanStatus::error);
}

TEST(FakeCanBus, FiltersDropNonMatchingIds) {
  auto net = FakeCanNetwork::create();
  auto tx = net->attach("tx");
  auto rx = net->attach("rx");
  const std::vector<CanFilter> only123{{0x123, 0x7FF, false}};
  ASSERT_TRUE(rx->set_filters(only123).ok());
  ASSERT_TRUE(tx->send(frame(0x321, {1})).ok());
  ASSERT_TRUE(tx->send(frame(0x123, {3}, true)).ok());  // extended: other kind
  ASSERT_TRUE(tx->send(frame(0x123, {2})).ok());
  CanFrame got;
  ASSERT_TRUE(rx->receive(got, 100ms).ok());
  EXPECT_TRUE(same_content(got, frame(0x123, {2})));
  EXPECT_EQ(rx->receive(got, 10ms).status, CanStatus::timeout);
  ASSERT_TRUE(rx->set_filters({}).ok());  // empty: everything again
  ASSERT_TRUE(tx->send(frame(0x321, {1})).ok());
  EXPECT_TRUE(rx->receive(got, 100ms).ok());
}

TEST(FakeCanBus, InjectedDropsLoseFramesSilently) {
  auto net = FakeCanNetwork::create();
  auto tx = net->attach();
  auto rx = net->attach();
  net->drop_next(2);
  for (std::uint8_t i = 0; i < 4; ++i) ASSERT_TRUE(tx->send(frame(0x10, {i})).ok());
  CanFrame got;
  ASSERT_TRUE(rx->receive(got, 100ms).ok());
  EXPECT_EQ(got.data[0], 2);
  ASSERT_TRUE(rx->receive(got, 100ms).ok());
  EXPECT_EQ(got.data[0], 3);
  EXPECT_EQ(net->dropped(), 2u);
  net->drop_if([](const CanFrame& f) { return f.id == 0x20; });
  ASSERT_TRUE(tx->send(frame(0x20, {})).ok());
  ASSERT_TRUE(tx->send(frame(0x21, {})).ok());
  ASSERT_TRUE(rx->receive(got, 100ms).ok());
  EXPECT_EQ(got.id, 0x21u);
  EXPECT_EQ(net->dropped(), 3u);
}

TEST(FakeCanBus, InjectedDelayHoldsFramesBack) {
  auto net = FakeCanNetwork::create();
  auto tx = net->attach();
  auto rx = net->attach();
  net->set_delay(50ms);
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_TRUE(tx->send(frame(0x1, {})).ok());
  CanFrame got;
  EXPECT_EQ(rx->receive(got, 5ms).status, CanStatus::timeout);  // not yet due
  ASSERT_TRUE(rx->receive(got, 2000ms).ok());
  EXPECT_GE(std::chrono::steady_clock::now() - t0, 50ms);
}

TEST(FakeCanBus, ReceiveWakesOnSendFromAnotherThread) {
  auto net = FakeCanNetwork::create();
  auto tx = net->attach();
  auto rx = net->attach();
  std::thread t([&] { EXPECT_TRUE(tx->send(frame(0x55, {0x55})).ok()); });
  CanFrame got;
  auto r = rx->receive(got, 5000ms);
  t.join();
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(got.id, 0x55u);
}

TEST(FakeCanBus, SendFullQueueIsRetryableNotFatal) {
  auto net = FakeCanNetwork::create();
  auto tx = net->attach("tx");
  net->fail_next_sends(1);
  auto r = tx->send(frame(0x1, {}));
  EXPECT_EQ(r.status, CanStatus::retry);
  EXPECT_EQ(r.error_number, ENOBUFS);
  EXPECT_TRUE(tx->send(frame(0x1, {})).ok());
}

TEST(FakeCanBus, ErrorFramesReportBusOff) {
  auto net = FakeCanNetwork::create();
  auto rx = net->attach("rx");
  net->inject_error_frame(CAN_ERR_BUSOFF);
  CanFrame got;
  auto r = rx->receive(got, 100ms);
  ASSERT_EQ(r.status, CanStatus::error_frame);
  EXPECT_TRUE(decode_error_frame(got).bus_off);
  EXPECT_NE(r.message.find("bus-off"), std::string::npos) << r.message;
}
