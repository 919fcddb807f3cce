// The fake GPIO chips obey the GpioLines contract (the same the gpio tests check on gpio-sim).
#include <gtest/gtest.h>

#include <cerrno>
#include <thread>

#include "fake_gpio_lines.h"

using namespace swum::io;
using namespace std::chrono_literals;

namespace {
struct FakeGpio : ::testing::Test {
  FakeGpio() { gpio.add_chip("gpiochip0", 8, "swum-sim"); }
  FakeGpioLines gpio;
};

template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const GpioError& e) {
    return e.what();
  }
  return "(no error)";
}
}  // namespace

TEST_F(FakeGpio, OutputValueIsSeenOutside) {
  auto out = gpio.request_output({"gpiochip0", 3, "test"}, false);
  EXPECT_FALSE(gpio.level("gpiochip0", 3));
  out->set(true);
  EXPECT_TRUE(gpio.level("gpiochip0", 3));
  EXPECT_TRUE(out->get());
  EXPECT_EQ(gpio.consumer("gpiochip0", 3), "test");
  out.reset();
  EXPECT_EQ(gpio.consumer("gpiochip0", 3), "");
}

TEST_F(FakeGpio, InputReadsPullAndDrive) {
  auto in = gpio.request_input({"gpiochip0", 4, "test"}, GpioEdge::none, GpioBias::as_is);
  gpio.set_pull("gpiochip0", 4, true);
  EXPECT_TRUE(in->get());
  gpio.set_pull("gpiochip0", 4, false);
  EXPECT_FALSE(in->get());
  gpio.drive("gpiochip0", 4, true);
  EXPECT_TRUE(in->get());
  gpio.drive("gpiochip0", 4, std::nullopt);
  EXPECT_FALSE(in->get());
  GpioEvent ev;
  EXPECT_NE(error_of([&] { in->wait_edge(ev, 1ms); }).find("without edge detection"), std::string::npos);
}

TEST_F(FakeGpio, RequestBiasSetsUndrivenLevel) {
  auto in = gpio.request_input({"gpiochip0", 1, "test"}, GpioEdge::none, GpioBias::pull_up);
  EXPECT_TRUE(in->get());
}

TEST_F(FakeGpio, EdgeEventsQueueAndTimeout) {
  auto in = gpio.request_input({"gpiochip0", 5, "test"}, GpioEdge::both, GpioBias::as_is);
  GpioEvent ev;
  EXPECT_EQ(in->wait_edge(ev, 10ms), GpioWait::timeout);
  gpio.set_pull("gpiochip0", 5, true);
  gpio.set_pull("gpiochip0", 5, false);
  ASSERT_EQ(in->wait_edge(ev, 1000ms), GpioWait::event);
  EXPECT_TRUE(ev.rising);
  ASSERT_EQ(in->wait_edge(ev, 1000ms), GpioWait::event);
  EXPECT_FALSE(ev.rising);
  EXPECT_EQ(in->wait_edge(ev, 10ms), GpioWait::timeout);
}

TEST_F(FakeGpio, RisingOnlyIgnoresFallingAndWakesAcrossThreads) {
  auto in = gpio.request_input({"gpiochip0", 6, "test"}, GpioEdge::rising, GpioBias::as_is);
  gpio.drive("gpiochip0", 6, true);
  gpio.drive("gpiochip0", 6, false);
  GpioEvent ev;
  ASSERT_EQ(in->wait_edge(ev, 1000ms), GpioWait::event);
  EXPECT_TRUE(ev.rising);
  EXPECT_EQ(in->wait_edge(ev, 10ms), GpioWait::timeout);
  std::thread t([&] { gpio.drive("gpiochip0", 6, true); });
  EXPECT_EQ(in->wait_edge(ev, 5000ms), GpioWait::event);
  t.join();
}

TEST_F(FakeGpio, ClearErrors) {
  EXPECT_NE(error_of([&] {
              gpio.request_output({"gpiochip9", 0, "t"}, false);
            }).find("no such GPIO chip 'gpiochip9'"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              gpio.request_output({"gpiochip0", 8, "t"}, false);
            }).find("offset out of range"),
            std::string::npos);
  auto held = gpio.request_output({"gpiochip0", 2, "holder"}, false);
  const auto busy = error_of([&] { gpio.request_input({"gpiochip0", 2, "t"}, GpioEdge::none, GpioBias::as_is); });
  EXPECT_NE(busy.find("busy"), std::string::npos) << busy;
  EXPECT_NE(busy.find("holder"), std::string::npos) << busy;
  try {
    gpio.request_output({"gpiochip0", 2, "t"}, false);
    ADD_FAILURE() << "no error";
  } catch (const GpioError& e) {
    EXPECT_EQ(e.error_number(), EBUSY);
  }
}
