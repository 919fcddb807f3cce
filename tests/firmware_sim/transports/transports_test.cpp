// CAN and GPIO transports against the in-process fakes (FakeCanNetwork, FakeGpioLines).
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <regex>
#include <string>
#include <thread>

#include "../emu_test_support.h"
#include "can_codec.h"
#include "fake_can_bus.h"
#include "fake_gpio_lines.h"
#include "transports/can_transport.h"
#include "transports/gpio_transport.h"

namespace swum::emu {
namespace {

using namespace std::chrono_literals;

using test::eventually;

class CanTransportTest : public ::testing::Test {
 protected:
  std::shared_ptr<io::FakeCanNetwork> network = io::FakeCanNetwork::create();
  std::unique_ptr<io::FakeCanBus> peer = network->attach("peer");
  SharedState shared;
  protocol::can::Ids ids = protocol::can::ids_for_node(3);
  std::unique_ptr<CanTransport> transport;

  void SetUp() override {
    CanTransportConfig config;
    config.node = 3;
    config.telemetry_hz = 500;
    config.heartbeat_s = 0.02;
    transport = std::make_unique<CanTransport>(network->attach("emu"), nullptr, config, shared, AmplifierLimits{});
    transport->start();
  }
  void TearDown() override { transport->stop(); }

  void send_command(std::uint8_t alive, double frequency = 40000, std::uint8_t mode = 1) {
    protocol::can::CommandFrame c;
    c.mode = mode;
    c.alive = alive;
    c.frequency_hz = frequency;
    c.amplitude_v = 400;
    ASSERT_TRUE(peer->send(protocol::can::encode_command(c, ids.command)).ok());
  }
  Reason wait_reject(std::uint64_t before) {
    EXPECT_TRUE(eventually([&] { return shared.rejects.count.load() > before; }));
    return static_cast<Reason>(shared.rejects.last_reason.load());
  }
  bool pop(Command& c) {
    return eventually([&] { return shared.commands.try_pop(c); }, 2000ms);
  }
};

std::int64_t monotonic_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

TEST_F(CanTransportTest, ValidCommandIsQueued) {
  const std::int64_t before = monotonic_now_ns();
  send_command(1);
  Command c;
  ASSERT_TRUE(pop(c));
  const std::int64_t after = monotonic_now_ns();
  EXPECT_EQ(c.source, CommandSource::can);
  EXPECT_EQ(c.action, Action::enable);
  EXPECT_NEAR(c.frequency_hz, 40000, 1e-9);
  EXPECT_NEAR(c.amplitude_v, 400, 1e-9);
  // The fake timestamps at delivery: the receive time is that, on CLOCK_MONOTONIC.
  EXPECT_GE(static_cast<std::int64_t>(c.accepted_ns), before - 1'000'000);  // clock-pair reading jitter
  EXPECT_LE(static_cast<std::int64_t>(c.accepted_ns), after);
  EXPECT_EQ(transport->stats().rx_stamped.load(), 1U);
  EXPECT_EQ(transport->stats().rx_stamp_missing.load(), 0U);
  EXPECT_EQ(transport->stats().rx_stamp_implausible.load(), 0U);
}

TEST(CanReceiveTime, ConvertsTheRealtimeStampToMonotonic) {
  using std::chrono::nanoseconds;
  const std::int64_t real = 1'700'000'000'000'000'000, mono = 5'000'000'000;
  RxStamp r = receive_time(nanoseconds(real - 250'000), real, mono);  // 250 us old
  EXPECT_EQ(r.source, RxStampSource::bus);
  EXPECT_EQ(r.age_ns, 250'000);
  EXPECT_EQ(r.monotonic_ns, mono - 250'000);
  r = receive_time(nanoseconds(real + 500'000), real, mono);  // 0.5 ms "in the future": jitter, age 0
  EXPECT_EQ(r.source, RxStampSource::bus);
  EXPECT_EQ(r.age_ns, 0);
  EXPECT_EQ(r.monotonic_ns, mono);
  r = receive_time(nanoseconds(0), real, mono);
  EXPECT_EQ(r.source, RxStampSource::missing);
  EXPECT_EQ(r.monotonic_ns, mono);
  r = receive_time(nanoseconds(real + 2'000'000), real, mono);  // clock stepped back
  EXPECT_EQ(r.source, RxStampSource::implausible);
  EXPECT_EQ(r.monotonic_ns, mono);
  r = receive_time(nanoseconds(real - kMaxFrameAgeNs - 1), real, mono);  // clock stepped forward
  EXPECT_EQ(r.source, RxStampSource::implausible);
  EXPECT_EQ(r.monotonic_ns, mono);
  r = receive_time(nanoseconds(real - 1000), -1, mono);  // realtime clock unreadable
  EXPECT_EQ(r.source, RxStampSource::implausible);
}

// A bus that hands the transport the fake's frames with their timestamp rewritten, as a kernel
// with queued frames (old timestamps) or without timestamps would.
class StampRewritingBus final : public io::CanBus {
 public:
  using Rewrite = std::function<std::chrono::nanoseconds(std::chrono::nanoseconds)>;
  StampRewritingBus(std::unique_ptr<io::CanBus> inner, Rewrite rewrite)
      : inner_(std::move(inner)), rewrite_(std::move(rewrite)) {}
  io::CanResult send(const io::CanFrame& frame) override { return inner_->send(frame); }
  io::CanResult receive(io::CanFrame& frame, std::chrono::milliseconds timeout) override {
    const io::CanResult r = inner_->receive(frame, timeout);
    if (r.ok()) frame.timestamp = rewrite_(frame.timestamp);
    return r;
  }
  io::CanResult set_filters(std::span<const io::CanFilter> filters) override { return inner_->set_filters(filters); }
  std::string name() const override { return inner_->name(); }

 private:
  std::unique_ptr<io::CanBus> inner_;
  Rewrite rewrite_;
};

struct StampedCommand {
  Command command;
  std::int64_t sent_ns = 0, popped_ns = 0;
  std::uint64_t stamped = 0, missing = 0, implausible = 0;
  std::uint64_t age_max_ns = 0;
};

StampedCommand command_through(const StampRewritingBus::Rewrite& rewrite) {
  auto network = io::FakeCanNetwork::create();
  auto peer = network->attach("peer");
  SharedState shared;
  CanTransportConfig config;
  config.node = 3;
  config.telemetry_hz = 0;
  config.heartbeat_s = 0;
  CanTransport transport(std::make_unique<StampRewritingBus>(network->attach("emu"), rewrite), nullptr, config, shared,
                         AmplifierLimits{});
  transport.start();
  StampedCommand out;
  protocol::can::CommandFrame c;
  c.mode = 1;
  c.alive = 1;
  c.amplitude_v = 100;
  out.sent_ns = monotonic_now_ns();
  EXPECT_TRUE(peer->send(protocol::can::encode_command(c, protocol::can::ids_for_node(3).command)).ok());
  EXPECT_TRUE(eventually([&] { return shared.commands.try_pop(out.command); }, 2000ms));
  out.popped_ns = monotonic_now_ns();
  transport.stop();
  out.stamped = transport.stats().rx_stamped.load();
  out.missing = transport.stats().rx_stamp_missing.load();
  out.implausible = transport.stats().rx_stamp_implausible.load();
  out.age_max_ns = transport.receive_age().max();
  return out;
}

TEST(CanTransportTimestamps, CommandReceiveTimeIsTheBusTimestamp) {
  // The frame "waited" 50 ms in the kernel's queue: the receive time is 50 ms before the read.
  const auto r = command_through([](std::chrono::nanoseconds t) { return t - 50ms; });
  EXPECT_EQ(r.stamped, 1U);
  EXPECT_EQ(r.missing + r.implausible, 0U);
  const auto accepted = static_cast<std::int64_t>(r.command.accepted_ns);
  EXPECT_GE(accepted, r.sent_ns - 51'000'000);
  EXPECT_LE(accepted, r.popped_ns - 50'000'000);
  EXPECT_GE(r.age_max_ns, 49'000'000U);  // histogram bucket resolution < 1.6 %
}

TEST(CanTransportTimestamps, MissingTimestampFallsBackToTheReadTimeAndIsCounted) {
  const auto r = command_through([](std::chrono::nanoseconds) { return std::chrono::nanoseconds(0); });
  EXPECT_EQ(r.missing, 1U);
  EXPECT_EQ(r.stamped + r.implausible, 0U);
  EXPECT_GE(static_cast<std::int64_t>(r.command.accepted_ns), r.sent_ns);
  EXPECT_LE(static_cast<std::int64_t>(r.command.accepted_ns), r.popped_ns);
  EXPECT_EQ(r.age_max_ns, 0U);
}

TEST(CanTransportTimestamps, SteppedClockIsNotTrusted) {
  const auto r = command_through([](std::chrono::nanoseconds t) { return t - 3600s; });
  EXPECT_EQ(r.implausible, 1U);
  EXPECT_EQ(r.stamped + r.missing, 0U);
  EXPECT_GE(static_cast<std::int64_t>(r.command.accepted_ns), r.sent_ns);
  EXPECT_LE(static_cast<std::int64_t>(r.command.accepted_ns), r.popped_ns);
}

TEST_F(CanTransportTest, InvalidFramesAreRejectedWithTheirReasonAndNotQueued) {
  send_command(1);
  Command c;
  ASSERT_TRUE(pop(c));
  std::uint64_t n = shared.rejects.count.load();
  send_command(1);  // repeated counter
  EXPECT_EQ(wait_reject(n), Reason::stale_alive_counter);
  n = shared.rejects.count.load();
  protocol::can::CommandFrame cf;
  cf.alive = 2;
  io::CanFrame bad = protocol::can::encode_command(cf, ids.command);
  bad.data[1] ^= 0xFF;
  ASSERT_TRUE(peer->send(bad).ok());
  EXPECT_EQ(wait_reject(n), Reason::bad_checksum);
  n = shared.rejects.count.load();
  bad = protocol::can::encode_command(cf, ids.command);
  bad.dlc = 4;
  ASSERT_TRUE(peer->send(bad).ok());
  EXPECT_EQ(wait_reject(n), Reason::wrong_length);
  n = shared.rejects.count.load();
  send_command(2, 60000);
  EXPECT_EQ(wait_reject(n), Reason::frequency_out_of_range);
  EXPECT_FALSE(shared.commands.try_pop(c));
  send_command(2);  // counter 2 was never accepted: still fresh
  ASSERT_TRUE(pop(c));
  EXPECT_EQ(transport->stats().accepted.load(), 2U);
}

TEST_F(CanTransportTest, TelemetryAndHeartbeatAreSent) {
  Telemetry t;
  t.state = AmpState::enabled;
  t.speed_m_s = 0.1985;
  shared.telemetry.store(t);
  bool status = false, motion = false, heartbeat = false;
  ASSERT_TRUE(eventually([&] {
    io::CanFrame f;
    while (peer->receive(f, 1ms).ok()) {
      if (f.id == ids.status && protocol::can::get_bits(f, 0, 2) == 1) status = true;
      if (f.id == ids.motion && protocol::can::get_bits(f, 0, 32) == 198500) motion = true;
      if (f.id == ids.heartbeat && f.dlc == 1 && f.data[0] == 5) heartbeat = true;
    }
    return status && motion && heartbeat;
  }));
}

TEST_F(CanTransportTest, SurvivesFullTransmitQueueAndBusOff) {
  network->fail_next_sends(20);
  network->inject_error_frame(0x40 /* CAN_ERR_BUSOFF */);
  ASSERT_TRUE(
      eventually([&] { return transport->stats().tx_dropped.load() >= 20 && transport->stats().bus_off.load() >= 1; }));
  send_command(5);
  Command c;
  ASSERT_TRUE(pop(c));
  const auto sent = transport->stats().tx_frames.load();
  ASSERT_TRUE(eventually([&] { return transport->stats().tx_frames.load() > sent + 10; }));
}

TEST(GpioTransport, EnableLineFaultLineAndEncoder) {
  io::FakeGpioLines lines;
  lines.add_chip("chip0", 8);
  lines.drive("chip0", 0, true);
  SharedState shared;
  GpioConfig config;
  ASSERT_EQ(parse_gpio_spec("chip0:enable=0,fault=1,a=2,b=3", config), "");
  config.encoder_resolution_m = 1e-6;
  config.max_edge_rate_hz = 20000;
  GpioTransport gpio(lines, config, shared);
  gpio.start();
  EXPECT_TRUE(shared.enable_line.load());
  lines.drive("chip0", 0, false);
  EXPECT_TRUE(eventually([&] { return !shared.enable_line.load(); }));
  lines.drive("chip0", 0, true);
  EXPECT_TRUE(eventually([&] { return shared.enable_line.load(); }));

  Telemetry t;
  t.state = AmpState::fault;
  shared.telemetry.store(t);
  EXPECT_TRUE(eventually([&] { return lines.level("chip0", 1); }));
  t.state = AmpState::disabled;
  shared.telemetry.store(t);
  EXPECT_TRUE(eventually([&] { return !lines.level("chip0", 1); }));

  // Encoder: +1.5 counts -> count 1 (A high, B low: A leads in +y); -0.5 -> count -1 (A low, B high).
  t.position_m = 1.5e-6;
  shared.telemetry.store(t);
  EXPECT_TRUE(eventually([&] { return gpio.stats().encoder_count.load() == 1; }));
  EXPECT_TRUE(lines.level("chip0", 2));
  EXPECT_FALSE(lines.level("chip0", 3));
  t.position_m = -0.5e-6;
  shared.telemetry.store(t);
  EXPECT_TRUE(eventually([&] { return gpio.stats().encoder_count.load() == -1; }));
  EXPECT_FALSE(lines.level("chip0", 2));
  EXPECT_TRUE(lines.level("chip0", 3));
  t.position_m = 100e-6;
  shared.telemetry.store(t);
  EXPECT_TRUE(eventually([&] { return gpio.stats().encoder_count.load() == 100; }));
  EXPECT_EQ(gpio.stats().encoder_edges.load(), 1U + 2U + 101U);
  gpio.stop();
}

// A line operation the kernel refuses must not end the process (an exception leaving the GPIO
// thread would call std::terminate): it is counted, the enable input reads as low while it
// cannot be read (drive off), and everything works again once the line does.
TEST(GpioTransport, LineErrorsAreCountedAndTheEnableInputFailsSafe) {
  io::FakeGpioLines lines;
  lines.add_chip("chip0", 8);
  lines.drive("chip0", 0, true);
  SharedState shared;
  GpioConfig config;
  ASSERT_EQ(parse_gpio_spec("chip0:enable=0,fault=1", config), "");
  GpioTransport gpio(lines, config, shared);
  gpio.start();
  ASSERT_TRUE(eventually([&] { return shared.enable_line.load(); }));

  lines.fail_operations("chip0", 0, true);
  lines.fail_operations("chip0", 1, true);
  Telemetry t;
  t.state = AmpState::fault;
  shared.telemetry.store(t);
  EXPECT_TRUE(eventually([&] { return !shared.enable_line.load() && gpio.stats().line_errors.load() >= 2; }));
  EXPECT_FALSE(lines.level("chip0", 1));  // the fault output could not be set

  lines.fail_operations("chip0", 0, false);
  lines.fail_operations("chip0", 1, false);
  EXPECT_TRUE(eventually([&] { return shared.enable_line.load(); }));
  EXPECT_TRUE(eventually([&] { return lines.level("chip0", 1); }));  // set once the line works
  // The loops kept only the first failure's status; its text is made for the report, here.
  testing::internal::CaptureStderr();
  gpio.stop();
  const std::string report = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(std::regex_match(report, std::regex(R"(swum-emu: GPIO: [0-9]+ line operations failed \(first: )"
                                                  R"(GPIO chip 'chip0' line [01]: (get|wait_edge|set) failed: )"
                                                  R"(Input/output error\)\n)")))
      << report;
  EXPECT_NE(report.find(gpio.first_error()), std::string::npos) << gpio.first_error();
}

TEST(GpioTransport, SpecParsing) {
  GpioConfig c;
  EXPECT_EQ(parse_gpio_spec("gpiochip1:enable=3,fault=4", c), "");
  EXPECT_EQ(c.chip, "gpiochip1");
  EXPECT_EQ(c.enable, 3);
  EXPECT_EQ(c.fault, 4);
  EXPECT_NE(parse_gpio_spec("gpiochip1:a=1", c), "");
  EXPECT_NE(parse_gpio_spec("gpiochip1:bogus=1", c), "");
  EXPECT_NE(parse_gpio_spec("nochip", c), "");
  // The line list is a comma list (src/formats/name_list.h): blanks around an entry dropped, an
  // empty entry refused (a trailing comma was accepted before the one splitter).
  GpioConfig spaced;
  EXPECT_EQ(parse_gpio_spec("gpiochip1: enable=5 , fault=6", spaced), "");
  EXPECT_EQ(spaced.enable, 5);
  EXPECT_EQ(spaced.fault, 6);
  GpioConfig empty;
  EXPECT_EQ(parse_gpio_spec("gpiochip1:enable=3,,fault=4", empty), "empty name in 'enable=3,,fault=4'");
  EXPECT_EQ(parse_gpio_spec("gpiochip1:enable=3,", empty), "empty name in 'enable=3,'");
  EXPECT_EQ(parse_gpio_spec("gpiochip1:", empty), "empty name in ''");
}

}  // namespace
}  // namespace swum::emu
