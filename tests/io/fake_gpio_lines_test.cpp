// The fake GPIO chips obey the GpioLines contract (the same the gpio tests check on gpio-sim).
#include <gtest/gtest.h>

#include <cerrno>
#include <thread>

#include "allocation_count.h"
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
// A line's value; a failed read fails the test.
template <class Line>
bool level_of(const Line& line) {
  bool value = false;
  const GpioResult r = line.get(value);
  EXPECT_TRUE(r.ok()) << r.operation << " failed, errno " << r.error_number;
  return value;
}
}  // namespace

TEST_F(FakeGpio, OutputValueIsSeenOutside) {
  auto out = gpio.request_output({"gpiochip0", 3, "test"}, false);
  EXPECT_FALSE(gpio.level("gpiochip0", 3));
  ASSERT_TRUE(out->set(true).ok());
  EXPECT_TRUE(gpio.level("gpiochip0", 3));
  EXPECT_TRUE(level_of(*out));
  EXPECT_EQ(gpio.consumer("gpiochip0", 3), "test");
  out.reset();
  EXPECT_EQ(gpio.consumer("gpiochip0", 3), "");
}

TEST_F(FakeGpio, InputReadsPullAndDrive) {
  auto in = gpio.request_input({"gpiochip0", 4, "test"}, GpioEdge::none, GpioBias::as_is);
  gpio.set_pull("gpiochip0", 4, true);
  EXPECT_TRUE(level_of(*in));
  gpio.set_pull("gpiochip0", 4, false);
  EXPECT_FALSE(level_of(*in));
  gpio.drive("gpiochip0", 4, true);
  EXPECT_TRUE(level_of(*in));
  gpio.drive("gpiochip0", 4, std::nullopt);
  EXPECT_FALSE(level_of(*in));
  GpioEvent ev;
  const GpioResult no_edges = in->wait_edge(ev, 1ms);  // a status, not an exception: a per-event call
  EXPECT_EQ(no_edges.status, GpioStatus::error);
  EXPECT_EQ(no_edges.error_number, EINVAL);
  const std::string text = describe(no_edges, {"gpiochip0", 4, "test"});
  EXPECT_NE(text.find("without edge detection"), std::string::npos) << text;
}

TEST_F(FakeGpio, RequestBiasSetsUndrivenLevel) {
  auto in = gpio.request_input({"gpiochip0", 1, "test"}, GpioEdge::none, GpioBias::pull_up);
  EXPECT_TRUE(level_of(*in));
}

TEST_F(FakeGpio, EdgeEventsQueueAndTimeout) {
  auto in = gpio.request_input({"gpiochip0", 5, "test"}, GpioEdge::both, GpioBias::as_is);
  GpioEvent ev;
  EXPECT_EQ(in->wait_edge(ev, 10ms).status, GpioStatus::timeout);
  gpio.set_pull("gpiochip0", 5, true);
  gpio.set_pull("gpiochip0", 5, false);
  ASSERT_EQ(in->wait_edge(ev, 1000ms).status, GpioStatus::ok);
  EXPECT_TRUE(ev.rising);
  ASSERT_EQ(in->wait_edge(ev, 1000ms).status, GpioStatus::ok);
  EXPECT_FALSE(ev.rising);
  EXPECT_EQ(in->wait_edge(ev, 10ms).status, GpioStatus::timeout);
}

TEST_F(FakeGpio, RisingOnlyIgnoresFallingAndWakesAcrossThreads) {
  auto in = gpio.request_input({"gpiochip0", 6, "test"}, GpioEdge::rising, GpioBias::as_is);
  gpio.drive("gpiochip0", 6, true);
  gpio.drive("gpiochip0", 6, false);
  GpioEvent ev;
  ASSERT_EQ(in->wait_edge(ev, 1000ms).status, GpioStatus::ok);
  EXPECT_TRUE(ev.rising);
  EXPECT_EQ(in->wait_edge(ev, 10ms).status, GpioStatus::timeout);
  std::thread t([&] { gpio.drive("gpiochip0", 6, true); });
  EXPECT_EQ(in->wait_edge(ev, 5000ms).status, GpioStatus::ok);
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

TEST_F(FakeGpio, InjectedFailuresReturnAStatusAndLeaveTheValue) {
  auto out = gpio.request_output({"gpiochip0", 3, "test"}, true);
  auto in = gpio.request_input({"gpiochip0", 4, "test"}, GpioEdge::both, GpioBias::pull_up);
  gpio.fail_operations("gpiochip0", 3, true);
  gpio.fail_operations("gpiochip0", 4, true);
  const GpioResult set = out->set(false);
  EXPECT_EQ(set.status, GpioStatus::error);
  EXPECT_EQ(set.error_number, EIO);
  EXPECT_EQ(describe(set, {"gpiochip0", 3, "test"}), "GPIO chip 'gpiochip0' line 3: set failed: Input/output error");
  EXPECT_TRUE(gpio.level("gpiochip0", 3));  // not changed
  bool value = false;
  EXPECT_EQ(in->get(value).status, GpioStatus::error);
  EXPECT_FALSE(value);  // untouched
  GpioEvent ev;
  EXPECT_EQ(in->wait_edge(ev, 1000ms).status, GpioStatus::error);  // at once, not after the timeout
  gpio.fail_operations("gpiochip0", 3, false);
  gpio.fail_operations("gpiochip0", 4, false);
  EXPECT_TRUE(out->set(false).ok());
  EXPECT_FALSE(gpio.level("gpiochip0", 3));
  EXPECT_TRUE(level_of(*in));
}

// A failing line's calls allocate nothing: the result names the call with a string literal and
// keeps the errno; the text is made only where it is reported (describe()), and says what it said.
TEST_F(FakeGpio, FailuresAllocateNothing) {
  auto out = gpio.request_output({"gpiochip0", 3, "test"}, false);
  auto in = gpio.request_input({"gpiochip0", 4, "test"}, GpioEdge::both, GpioBias::as_is);
  auto plain = gpio.request_input({"gpiochip0", 5, "test"}, GpioEdge::none, GpioBias::as_is);
  gpio.fail_operations("gpiochip0", 3, true);
  gpio.fail_operations("gpiochip0", 4, true);
  GpioResult set, get_out, get_in, wait, misuse;
  bool value = false;
  GpioEvent ev;
  const long before = swum::test::allocation_count();
  for (int k = 0; k < 1000; ++k) {  // a second of the transport's retries
    set = out->set(true);
    get_out = out->get(value);
    get_in = in->get(value);
    wait = in->wait_edge(ev, 1ms);  // a failure returns at once; 1 ms bounds a wait that did not fail
    misuse = plain->wait_edge(ev, 1ms);
  }
  const long allocated = swum::test::allocation_count() - before;
  EXPECT_EQ(allocated, 0);
  for (const GpioResult* r : {&set, &get_out, &get_in, &wait, &misuse}) EXPECT_EQ(r->status, GpioStatus::error);
  EXPECT_EQ(describe(set, {"gpiochip0", 3, "test"}), "GPIO chip 'gpiochip0' line 3: set failed: Input/output error");
  EXPECT_EQ(describe(get_out, {"gpiochip0", 3, "test"}),
            "GPIO chip 'gpiochip0' line 3: get failed: Input/output error");
  EXPECT_EQ(describe(get_in, {"gpiochip0", 4, "test"}), "GPIO chip 'gpiochip0' line 4: get failed: Input/output error");
  EXPECT_EQ(describe(wait, {"gpiochip0", 4, "test"}),
            "GPIO chip 'gpiochip0' line 4: wait_edge failed: Input/output error");
  EXPECT_EQ(misuse.error_number, EINVAL);
  EXPECT_EQ(describe(misuse, {"gpiochip0", 5, "test"}),
            "GPIO chip 'gpiochip0' line 5: wait_edge (line requested without edge detection) failed: Invalid argument");
}
