// The host's CAN adapter against a node on the in-process fake bus that speaks the emulator's
// frames (encoders and command decoder of protocol/can_codec.h): telemetry sets with the
// device clock, valid command frames (CRC, alive counter), absent node, bus-off.
#include "device/can_device.h"

#include <gtest/gtest.h>

#include <linux/can/error.h>
#include <chrono>

#include <atomic>
#include <mutex>
#include <thread>

#include "can_codec.h"
#include "fake_can_bus.h"

namespace swum::host {
namespace {

namespace can = protocol::can;

class FakeNode {
 public:
  // electrical: send the ElectricalA/B frames (a board of the older protocol does not).
  FakeNode(std::shared_ptr<io::FakeCanNetwork> network, std::uint8_t node, bool electrical = true)
      : bus_(network->attach("node")), ids_(protocol::can::ids_for_node(node)), electrical_(electrical) {
    telemetry_.state = protocol::AmpState::enabled;
    telemetry_.electrical = {0.1834, 0.1791, 61.23, 58.77, -4.32, 3.22, 8.77, 8.12};
    telemetry_.stator_temperature_c = 21.5;
    telemetry_.output.amplitude_v = 250.0;
    telemetry_.output.frequency_hz = 40123.0;
    telemetry_.speed_m_s = 0.321;
    telemetry_.sim_time_s = 12.5;
    thread_ = std::thread([this] { run(); });
  }
  ~FakeNode() {
    stop_ = true;
    thread_.join();
  }
  struct Received {
    protocol::Reason reason;
    protocol::can::CommandFrame frame;
  };
  std::vector<Received> commands() {
    std::lock_guard lock(mutex_);
    return commands_;
  }

 private:
  void run() {
    std::uint8_t counter = 0;
    protocol::can::AliveCounter alive;
    auto next = std::chrono::steady_clock::now();
    while (!stop_) {
      io::CanFrame f;
      if (bus_->receive(f, std::chrono::milliseconds(1)).ok() && f.id == ids_.command) {
        Received r{};
        r.reason = protocol::can::decode_command(f, r.frame);
        if (r.reason == protocol::Reason::none) r.reason = alive.check(r.frame.alive, 0);
        if (r.reason == protocol::Reason::none) alive.accept(r.frame.alive, 0);
        std::lock_guard lock(mutex_);
        commands_.push_back(r);
      }
      if (std::chrono::steady_clock::now() >= next) {
        next += std::chrono::milliseconds(2);
        telemetry_.sim_time_s += 0.002;
        (void)bus_->send(protocol::can::encode_status(telemetry_, {}, counter++, ids_.status));
        (void)bus_->send(protocol::can::encode_motion(telemetry_, ids_.motion));
        (void)bus_->send(protocol::can::encode_drive(telemetry_, ids_.drive));
        (void)bus_->send(protocol::can::encode_loop_stats(telemetry_, ids_.loop_stats));
        (void)bus_->send(protocol::can::encode_clock(telemetry_, ids_.clock));
        if (electrical_) {
          (void)bus_->send(protocol::can::encode_electrical_a(telemetry_, ids_.electrical_a));
          (void)bus_->send(protocol::can::encode_electrical_b(telemetry_, ids_.electrical_b));
        }
        (void)bus_->send(protocol::can::encode_output(telemetry_, ids_.output));
      }
    }
  }
  std::unique_ptr<io::FakeCanBus> bus_;
  protocol::can::Ids ids_;
  bool electrical_;
  protocol::Telemetry telemetry_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::vector<Received> commands_;
  std::thread thread_;
};

const DeviceTimeouts kTimeouts{std::chrono::milliseconds(500), std::chrono::milliseconds(200)};

TEST(CanDevice, ReadsCompleteTelemetrySetsWithTheDeviceClock) {
  auto network = io::FakeCanNetwork::create();
  FakeNode node(network, 7);
  CanDevice device(network->attach("host"), 7, kTimeouts);
  const DeviceTelemetry a = device.read();
  const DeviceTelemetry b = device.read();
  EXPECT_EQ(a.state, 1);
  EXPECT_NEAR(a.speed_mm_s, 321.0, 1e-3);
  EXPECT_NEAR(a.amplitude_v, 250.0, 0.05);
  EXPECT_NEAR(a.frequency_hz, 40123.0, 1e-3);
  ASSERT_TRUE(a.device_time_s && b.device_time_s);
  EXPECT_GT(*b.device_time_s, *a.device_time_s);
  ASSERT_TRUE(a.sample_counter && b.sample_counter);
  EXPECT_EQ(a.sample_counter_modulus, 256u);
  EXPECT_EQ(device.name(), "can host node 7");
}

TEST(CanDevice, ReadsTheElectricalFramesOfASet) {
  auto network = io::FakeCanNetwork::create();
  FakeNode node(network, 7);
  CanDevice device(network->attach("host"), 7, kTimeouts);
  const DeviceTelemetry t = device.read();
  ASSERT_TRUE(t.electrical && t.stator_temperature_c);
  EXPECT_NEAR(t.electrical->current_a_a, 0.1834, 1e-4);
  EXPECT_NEAR(t.electrical->current_b_a, 0.1791, 1e-4);
  EXPECT_NEAR(t.electrical->phase_a_deg, 61.23, 0.01);
  EXPECT_NEAR(t.electrical->motional_phase_b_deg, 3.22, 0.01);
  EXPECT_NEAR(t.electrical->power_w(), 16.89, 0.02);
  EXPECT_NEAR(*t.stator_temperature_c, 21.5, 0.01);
}

// A board that does not send ElectricalA/B: its sets are complete at Output as before, without
// electrical values, and its Status bytes 6-7 are not read as a temperature.
TEST(CanDevice, ASetWithoutTheElectricalFramesIsCompleteWithoutThem) {
  auto network = io::FakeCanNetwork::create();
  FakeNode node(network, 7, false);
  CanDevice device(network->attach("host"), 7, kTimeouts);
  const DeviceTelemetry t = device.read();
  EXPECT_NEAR(t.speed_mm_s, 321.0, 1e-3);
  EXPECT_FALSE(t.electrical);
  EXPECT_FALSE(t.stator_temperature_c);
}

TEST(CanDevice, SendsValidCommandFramesWithAdvancingAliveCounters) {
  auto network = io::FakeCanNetwork::create();
  FakeNode node(network, 7);
  {
    CanDevice device(network->attach("host"), 7, kTimeouts);
    device.set_drive({39876.5, 321.25, -90.0, 0.0});
    device.command(DeviceAction::enable);
    for (int i = 0; i < 40; ++i) device.command(DeviceAction::keep_alive);  // wraps the 4-bit counter
    device.command(DeviceAction::disable);
    device.command(DeviceAction::reset_fault);
    (void)device.read();
  }
  // The node's thread takes the frames off the bus on its own schedule (slow on a loaded
  // machine): wait until it has all 44, with a deadline, rather than assume it has.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (node.commands().size() < 44u && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::yield();
  }
  const auto commands = node.commands();
  ASSERT_EQ(commands.size(), 44u);
  for (const auto& c : commands) EXPECT_EQ(c.reason, protocol::Reason::none) << protocol::to_string(c.reason);
  EXPECT_EQ(commands[0].frame.mode, 0);  // setpoint while disabled
  EXPECT_NEAR(commands[0].frame.frequency_hz, 39876.5, 0.05);
  EXPECT_NEAR(commands[0].frame.amplitude_v, 321.25, 0.125);
  EXPECT_NEAR(commands[0].frame.phase_deg, -90.0, 0.05);
  EXPECT_EQ(commands[1].frame.mode, 1);   // enable
  EXPECT_EQ(commands[20].frame.mode, 1);  // keep-alives repeat the mode
  EXPECT_EQ(commands[42].frame.mode, 0);  // disable
  EXPECT_EQ(commands[43].frame.mode, 2);  // reset fault
}

TEST(CanDevice, AnAbsentNodeIsNamedInTheError) {
  auto network = io::FakeCanNetwork::create();
  FakeNode node(network, 7);
  try {
    CanDevice device(network->attach("host"), 4, kTimeouts);
    FAIL() << "no error";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("no answer from node 4"), std::string::npos) << e.what();
  }
}

TEST(CanDevice, ASetWithAFrameLostIsDroppedNotFilledWithZeros) {
  auto network = io::FakeCanNetwork::create();
  FakeNode node(network, 7);
  CanDevice device(network->attach("host"), 7, kTimeouts);
  const std::uint32_t motion = protocol::can::ids_for_node(7).motion;
  network->drop_if([motion](const io::CanFrame& f) { return f.id == motion; });
  // Sets the node completed before the filter went in may still be queued: those come back
  // whole (never zero-filled); then every set lacks its Motion frame and reading must fail.
  bool threw = false;
  for (int k = 0; k < 10 && !threw; ++k) {
    try {
      const DeviceTelemetry queued = device.read();
      EXPECT_NEAR(queued.speed_mm_s, 321.0, 1e-3) << "a set returned with a frame missing";
    } catch (const DeviceError&) {
      threw = true;
    }
  }
  EXPECT_TRUE(threw) << "every set lacks its Motion frame, yet reads kept succeeding";
  network->drop_if(nullptr);
  const DeviceTelemetry t = device.read();
  EXPECT_NEAR(t.speed_mm_s, 321.0, 1e-3);
}

TEST(CanDevice, BusOffIsAnError) {
  auto network = io::FakeCanNetwork::create();
  FakeNode node(network, 7);
  CanDevice device(network->attach("host"), 7, kTimeouts);
  network->inject_error_frame(CAN_ERR_BUSOFF);
  bool threw = false;
  for (int i = 0; i < 5 && !threw; ++i) {
    try {
      (void)device.read();
    } catch (const DeviceError& e) {
      threw = true;
      EXPECT_NE(std::string(e.what()).find("bus-off"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(threw);
}

TEST(CanDevice, MalformedAddressesAreUsageErrors) {
  EXPECT_THROW(CanDevice(":3", kTimeouts), std::invalid_argument);
  EXPECT_THROW(CanDevice("vcan0:0", kTimeouts), std::invalid_argument);
  EXPECT_THROW(CanDevice("vcan0:128", kTimeouts), std::invalid_argument);
  EXPECT_THROW(CanDevice("vcan0:x", kTimeouts), std::invalid_argument);
}

}  // namespace
}  // namespace swum::host
