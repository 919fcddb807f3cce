// GpiodLines against the kernel's gpio-sim chip "swum" (tools/vm/gpio-sim-chip): the simulated
// side is driven and read through the sim's sysfs, the line side through the adapter. Runs in the
// test guest (tools/vm/with-gpio-sim), or natively where that chip is live.
#include <gtest/gtest.h>

#include <cerrno>
#include <fstream>

#include "gpiod_lines.h"

using namespace swum::io;
using namespace std::chrono_literals;

namespace {
constexpr auto kWait = 10000ms;

std::string read_line(const std::string& path) {
  std::ifstream in(path);
  std::string s;
  std::getline(in, s);
  return s;
}

struct GpioSim : ::testing::Test {
  void SetUp() override {
    const char* env = std::getenv("SWUM_GPIO_SIM");
    cfg = env ? env : "/sys/kernel/config/gpio-sim/swum";
    chip = read_line(cfg + "/bank0/chip_name");
    const std::string dev = read_line(cfg + "/dev_name");
    ASSERT_FALSE(chip.empty()) << "gpio-sim chip not configured at " << cfg << " (see tools/vm/gpio-sim-chip)";
    sysfs = "/sys/devices/platform/" + dev + "/" + chip;
  }
  std::string sim(unsigned offset, const char* attr) const {
    return sysfs + "/sim_gpio" + std::to_string(offset) + "/" + attr;
  }
  void set_pull(unsigned offset, const char* pull) const {
    std::ofstream out(sim(offset, "pull"));
    out << pull;
    out.close();
    ASSERT_TRUE(out) << "cannot write " << sim(offset, "pull");
  }
  template <class F>
  static std::pair<std::string, int> error_of(F f) {
    try {
      f();
    } catch (const GpioError& e) {
      return {e.what(), e.error_number()};
    }
    return {"(no error)", 0};
  }
  // A line's value; a failed read fails the test.
  template <class Line>
  static bool level_of(const Line& line) {
    bool value = false;
    const GpioResult r = line.get(value);
    EXPECT_TRUE(r.ok()) << r.operation << " failed, errno " << r.error_number;
    return value;
  }
  // Takes the chip away (gpio-sim's configfs `live`) or brings it back, as a driver unbinding.
  void set_live(bool live) const {
    std::ofstream out(cfg + "/live");
    out << (live ? "1" : "0");
    out.close();
    ASSERT_TRUE(out) << "cannot write " << cfg << "/live";
  }
  std::string cfg, chip, sysfs;
  GpiodLines gpio;
};
}  // namespace

TEST_F(GpioSim, OutputShowsInSimSysfs) {
  auto out = gpio.request_output({chip, 3, "swum-test"}, false);
  EXPECT_EQ(read_line(sim(3, "value")), "0");
  ASSERT_TRUE(out->set(true).ok());
  EXPECT_EQ(read_line(sim(3, "value")), "1");
  EXPECT_TRUE(level_of(*out));
  ASSERT_TRUE(out->set(false).ok());
  EXPECT_EQ(read_line(sim(3, "value")), "0");
}

TEST_F(GpioSim, SimPullIsReadThroughInput) {
  auto in = gpio.request_input({chip, 4, "swum-test"}, GpioEdge::none, GpioBias::as_is);
  set_pull(4, "pull-up");
  EXPECT_TRUE(level_of(*in));
  set_pull(4, "pull-down");
  EXPECT_FALSE(level_of(*in));
}

TEST_F(GpioSim, RequestBiasReachesTheSim) {
  auto in = gpio.request_input({chip, 1, "swum-test"}, GpioEdge::none, GpioBias::pull_up);
  EXPECT_EQ(read_line(sim(1, "pull")), "pull-up");
  EXPECT_TRUE(level_of(*in));
}

TEST_F(GpioSim, EdgeEventsArriveThroughWait) {
  set_pull(5, "pull-down");
  auto in = gpio.request_input({chip, 5, "swum-test"}, GpioEdge::both, GpioBias::as_is);
  GpioEvent ev;
  EXPECT_EQ(in->wait_edge(ev, 50ms).status, GpioStatus::timeout);
  set_pull(5, "pull-up");
  ASSERT_EQ(in->wait_edge(ev, kWait).status, GpioStatus::ok);
  EXPECT_TRUE(ev.rising);
  EXPECT_GT(ev.timestamp.count(), 0);
  set_pull(5, "pull-down");
  ASSERT_EQ(in->wait_edge(ev, kWait).status, GpioStatus::ok);
  EXPECT_FALSE(ev.rising);
  EXPECT_EQ(in->wait_edge(ev, 50ms).status, GpioStatus::timeout);
}

TEST_F(GpioSim, ClearErrors) {
  auto [no_chip, e1] = error_of([&] { gpio.request_output({"gpiochip99", 0, "t"}, false); });
  EXPECT_NE(no_chip.find("no such GPIO chip 'gpiochip99'"), std::string::npos) << no_chip;
  auto [range, e2] = error_of([&] { gpio.request_output({chip, 8, "t"}, false); });
  EXPECT_NE(range.find("offset out of range"), std::string::npos) << range;
  EXPECT_NE(range.find("has 8 lines"), std::string::npos) << range;
  auto held = gpio.request_output({chip, 6, "holder"}, false);
  auto [busy, e3] = error_of([&] { gpio.request_input({chip, 6, "t"}, GpioEdge::none, GpioBias::as_is); });
  EXPECT_NE(busy.find("busy"), std::string::npos) << busy;
  EXPECT_NE(busy.find("holder"), std::string::npos) << busy;
  EXPECT_EQ(e3, EBUSY);
  auto in = gpio.request_input({chip, 7, "t"}, GpioEdge::none, GpioBias::as_is);
  GpioEvent ev;
  const GpioResult no_edges = in->wait_edge(ev, 1ms);  // a status, not an exception: a per-event call
  EXPECT_EQ(no_edges.status, GpioStatus::error);
  EXPECT_EQ(no_edges.error_number, EINVAL);
  const std::string text = describe(no_edges, {chip, 7, "t"});
  EXPECT_NE(text.find("without edge detection"), std::string::npos) << text;
}

// The kernel refusing a per-event call (the chip removed under requested lines: its ioctls and
// reads fail with ENODEV) comes back as a status with libgpiod's errno, not as an exception: the
// adapter's conversion of libgpiod's std::system_error. The chip is made live again afterwards.
TEST_F(GpioSim, ChipRemovedUnderHeldLinesGivesStatuses) {
  auto out = gpio.request_output({chip, 2, "swum-test"}, false);
  auto in = gpio.request_input({chip, 3, "swum-test"}, GpioEdge::both, GpioBias::as_is);
  ASSERT_TRUE(out->set(true).ok());
  set_live(false);
  struct Relive {
    const GpioSim& sim;
    ~Relive() { sim.set_live(true); }
  } relive{*this};
  GpioResult set, get, wait;
  bool value = false;
  GpioEvent ev;
  EXPECT_NO_THROW(set = out->set(false));
  EXPECT_NO_THROW(get = in->get(value));
  EXPECT_NO_THROW(wait = in->wait_edge(ev, 1000ms));  // the waiter wakes up to the gone chip
  EXPECT_EQ(describe(set, {chip, 2, "swum-test"}), "GPIO chip '" + chip + "' line 2: set failed: No such device");
  EXPECT_EQ(describe(get, {chip, 3, "swum-test"}), "GPIO chip '" + chip + "' line 3: get failed: No such device");
  EXPECT_EQ(describe(wait, {chip, 3, "swum-test"}),
            "GPIO chip '" + chip + "' line 3: wait_edge failed: No such device");
  for (const GpioResult* r : {&set, &get, &wait}) {
    EXPECT_EQ(r->status, GpioStatus::error);
    EXPECT_EQ(r->error_number, ENODEV);
  }
}
