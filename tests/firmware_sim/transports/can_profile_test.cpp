// The CAN profile seam (transports/can_profile.h) on the fake bus: a stand-in profile of the
// kind the next one will be (a CANopen node: a request answered on the bus, a command from a
// 29-bit identifier, frames of its own each telemetry period and on its own schedule), so the
// transport is seen to leave the frame set to the profile and to keep sockets, statistics,
// recording and the scenario's faults to itself. Also the --record-can line of an extended frame.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "../emu_test_support.h"
#include "fake_can_bus.h"
#include "transports/can_transport.h"

namespace swum::emu {
namespace {

using namespace std::chrono_literals;
using test::eventually;

constexpr std::uint32_t kRequestId = 0x601;       // answered on kReplyId with the same payload
constexpr std::uint32_t kReplyId = 0x581;         //
constexpr std::uint32_t kCommandId = 0x1ABCDEF0;  // extended: an enable command
constexpr std::uint32_t kTelemetryId = 0x181;     // one frame per telemetry set
constexpr std::uint32_t kPeriodicId = 0x701;      // one frame per send_periodic() call

io::CanFrame frame(std::uint32_t id, bool extended, std::vector<std::uint8_t> data) {
  io::CanFrame f;
  f.id = id;
  f.extended = extended;
  f.dlc = static_cast<std::uint8_t>(data.size());
  for (std::size_t i = 0; i < data.size(); ++i) f.data[i] = data[i];
  return f;
}

class StandInProfile final : public CanProfile {
 public:
  [[nodiscard]] std::span<const io::CanFilter> filters() const override { return filters_; }
  CanRxResult receive(const io::CanFrame& f, const CanRxTime& time, CanNodePort& node) override {
    last_receive_ns = time.receive_ns;
    if (f.dlc == 0) return {CanRxStatus::refused, Reason::wrong_length};
    if (!f.extended && f.id == kRequestId) {
      io::CanFrame reply = f;
      reply.id = kReplyId;
      node.send(reply);  // a reply from the receive path, as an SDO server answers
      return {CanRxStatus::accepted, Reason::none};
    }
    if (f.extended && f.id == kCommandId) {
      Command c;
      c.fields = Command::kAction;
      c.action = Action::enable;
      c.source = CommandSource::can;
      const Reason r = node.submit(c);
      return {r == Reason::none ? CanRxStatus::accepted : CanRxStatus::refused, r};
    }
    return {};
  }
  void send_telemetry(const Telemetry& t, const RejectSnapshot&, CanSender& out) override {
    out.send(frame(kTelemetryId, false, {static_cast<std::uint8_t>(t.tick & 0xFF)}));
  }
  void send_periodic(std::int64_t, CanSender& out) override { out.send(frame(kPeriodicId, false, {0x05})); }

  std::int64_t last_receive_ns = 0;  // receive thread; read after a frame was seen handled

 private:
  std::array<io::CanFilter, 2> filters_{io::CanFilter{kRequestId, io::kCanStandardIdMax, false},
                                        io::CanFilter{kCommandId, io::kCanExtendedIdMax, true}};
};

struct ProfileRig {
  std::shared_ptr<io::FakeCanNetwork> network = io::FakeCanNetwork::create();
  std::unique_ptr<io::FakeCanBus> peer = network->attach("peer");
  SharedState shared;
  StandInProfile* profile = nullptr;
  std::unique_ptr<CanTransport> transport;

  explicit ProfileRig(std::FILE* log = nullptr) {
    auto p = std::make_unique<StandInProfile>();
    profile = p.get();
    CanTransportConfig config;
    config.telemetry_hz = 500;
    config.can_log = log;
    transport = std::make_unique<CanTransport>(network->attach("emu"), nullptr, std::move(p), config, shared,
                                               AmplifierLimits{});
    transport->start();
  }
  // The next frame from the node with identifier `id` (others skipped).
  bool receive(std::uint32_t id, io::CanFrame& out) {
    return eventually([&] { return peer->receive(out, 1ms).ok() && out.id == id; }, 2000ms);
  }
};

TEST(CanProfile, TheProfileReadsAndAnswersTheTransportCounts) {
  ProfileRig rig;
  ASSERT_TRUE(rig.peer->send(frame(kRequestId, false, {0x40, 0x41, 0x60, 0x00})).ok());
  io::CanFrame reply;
  ASSERT_TRUE(rig.receive(kReplyId, reply));
  EXPECT_EQ(io::to_cansend(reply), "581#40416000");

  ASSERT_TRUE(rig.peer->send(frame(kCommandId, true, {0x01})).ok());
  Command c;
  ASSERT_TRUE(eventually([&] { return rig.shared.commands.try_pop(c); }));
  EXPECT_EQ(c.action, Action::enable);
  EXPECT_NE(c.accepted_ns, 0U);  // stamped by the transport with the frame's receive time
  EXPECT_EQ(static_cast<std::int64_t>(c.accepted_ns), rig.profile->last_receive_ns);

  const std::uint64_t rejects = rig.shared.rejects.count.load();
  ASSERT_TRUE(rig.peer->send(frame(kRequestId, false, {})).ok());  // refused by the profile
  ASSERT_TRUE(eventually([&] { return rig.shared.rejects.count.load() > rejects; }));
  EXPECT_EQ(static_cast<Reason>(rig.shared.rejects.last_reason.load()), Reason::wrong_length);
  EXPECT_EQ(static_cast<CommandSource>(rig.shared.rejects.last_source.load()), CommandSource::can);

  ASSERT_TRUE(rig.peer->send(frame(0x123, false, {0x01})).ok());  // outside the profile's filters
  // A frame the filters pass, sent after 0x123 and answered: once its reply is seen, the node has
  // read everything sent before it, so a 0x123 that got through would have been counted.
  ASSERT_TRUE(rig.peer->send(frame(kRequestId, false, {0x2B})).ok());
  ASSERT_TRUE(rig.receive(kReplyId, reply));
  EXPECT_EQ(io::to_cansend(reply), "581#2B");
  io::CanFrame f;
  EXPECT_TRUE(rig.receive(kTelemetryId, f));  // the profile's own frames flow
  EXPECT_TRUE(rig.receive(kPeriodicId, f));
  rig.transport->stop();
  EXPECT_EQ(rig.transport->stats().rx_frames.load(), 4U);  // 0x123 never reached the node
  EXPECT_EQ(rig.transport->stats().accepted.load(), 3U);
  EXPECT_EQ(rig.transport->stats().rejected.load(), 1U);
}

TEST(CanProfile, TheCommFaultGateHoldsForEveryProfile) {
  ProfileRig rig;
  rig.shared.can_faults.set({.off = true});
  std::this_thread::sleep_for(20ms);
  io::CanFrame f;
  while (rig.peer->receive(f, 1ms).ok()) {
  }  // what went out before the bus-off
  ASSERT_TRUE(rig.peer->send(frame(kRequestId, false, {0x01})).ok());
  ASSERT_TRUE(eventually([&] { return rig.transport->stats().bus_off_discarded.load() == 1; }));
  EXPECT_FALSE(rig.peer->receive(f, 50ms).ok());  // neither a reply, nor telemetry, nor periodic frames
  rig.shared.can_faults.set({.off = false});
  EXPECT_TRUE(rig.receive(kTelemetryId, f));
}

// --record-can writes the protocol's cansend text: 3 hex digits for a standard identifier,
// 8 for an extended one (candump's own form), received and sent alike.
TEST(CanProfile, RecordingWritesExtendedIdentifiersInFull) {
  std::FILE* log = std::tmpfile();
  ASSERT_NE(log, nullptr);
  {
    ProfileRig rig(log);
    ASSERT_TRUE(rig.peer->send(frame(kCommandId, true, {0xDE, 0xAD})).ok());
    ASSERT_TRUE(rig.peer->send(frame(kRequestId, false, {0xAA, 0xBB})).ok());
    io::CanFrame f;
    ASSERT_TRUE(rig.receive(kReplyId, f));
    ASSERT_TRUE(rig.receive(kPeriodicId, f));  // the transmit thread has run (it may start late)
    rig.transport->stop();
  }
  std::rewind(log);
  std::vector<std::string> lines;
  char line[256];
  while (std::fgets(line, sizeof line, log) != nullptr) lines.emplace_back(line);
  std::fclose(log);
  auto has = [&](const std::string& tail) {
    for (const auto& l : lines) {
      // "(SECONDS.MICROSECONDS) emu ID#DATA\n"
      if (l.size() > tail.size() && l.compare(l.size() - tail.size(), tail.size(), tail) == 0 && l[0] == '(' &&
          l.find(") emu ") != std::string::npos && l[l.find('.') + 7] == ')')
        return true;
    }
    return false;
  };
  EXPECT_TRUE(has(" emu 1ABCDEF0#DEAD\n"));
  EXPECT_TRUE(has(" emu 601#AABB\n"));
  EXPECT_TRUE(has(" emu 581#AABB\n"));
  EXPECT_TRUE(has(" emu 701#05\n"));  // wall clock: recorded (lockstep leaves these out)
}

}  // namespace
}  // namespace swum::emu
