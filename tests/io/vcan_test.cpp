// SocketCanBus against a real (virtual) CAN bus and can-utils as the independent peer. Runs
// where vcan0/vcan1 exist: natively, or in the test guest (tools/vm/with-vcan). Functional and
// protocol checks only: no real-time figures are asserted (the guest runs under TCG).
#include <gtest/gtest.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include "child_process.h"
#include "socketcan_bus.h"

using namespace swum::io;
using swum::test::ChildProcess;
using namespace std::chrono_literals;

namespace {
constexpr auto kWait = 10000ms;  // generous: the guest is slow, but nothing may hang

std::chrono::nanoseconds now_realtime() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch());
}

void run_ok(std::vector<std::string> argv) {
  const std::string cmd = argv[0] + " " + argv.back();
  const auto rc = swum::test::run(std::move(argv), kWait);
  ASSERT_TRUE(rc.has_value()) << cmd << " did not finish";
  ASSERT_EQ(*rc, 0) << cmd;
}

// Receivers registered on `ifname` in the kernel's CAN receive lists (/proc/net/can/rcvlist_*):
// an explicit readiness signal for a peer's socket being bound with its filters.
int kernel_receivers(const std::string& ifname) {
  int count = 0;
  for (const char* list : {"all", "fil", "inv", "sff", "eff", "err"}) {
    std::ifstream in(std::string("/proc/net/can/rcvlist_") + list);
    std::string line;
    while (std::getline(in, line)) {
      std::istringstream words(line);
      std::string first;
      words >> first;
      if (first == ifname) ++count;
    }
  }
  return count;
}
}  // namespace

// (1) cansend from can-utils -> the project's SocketCanBus.
TEST(Vcan, CansendToAdapter) {
  SocketCanBus bus("vcan0");  // bound before the peer sends
  const auto before = now_realtime();
  run_ok({"cansend", "vcan0", "123#DEADBEEF"});
  CanFrame f;
  const auto r = bus.receive(f, kWait);
  ASSERT_EQ(r.status, CanStatus::ok) << r.message;
  EXPECT_EQ(f.id, 0x123u);
  EXPECT_FALSE(f.extended);
  ASSERT_EQ(f.dlc, 4);
  EXPECT_EQ(f.data[0], 0xDE);
  EXPECT_EQ(f.data[1], 0xAD);
  EXPECT_EQ(f.data[2], 0xBE);
  EXPECT_EQ(f.data[3], 0xEF);
  // Kernel receive timestamp (CLOCK_REALTIME): after the peer started, before we returned.
  EXPECT_GE(f.timestamp, before);
  EXPECT_LE(f.timestamp, now_realtime());
  EXPECT_EQ(bus.kernel_drops(), 0u);
}

// (2) the project's SocketCanBus -> candump from can-utils.
TEST(Vcan, AdapterToCandump) {
  SocketCanBus bus("vcan0");
  const int receivers_before = kernel_receivers("vcan0");
  ChildProcess candump({"candump", "-n", "1", "vcan0"}, true);
  ASSERT_TRUE(swum::test::wait_until([&] { return kernel_receivers("vcan0") > receivers_before; }, kWait))
      << "candump never registered a receiver on vcan0";
  CanFrame f;
  f.id = 0x321;
  f.dlc = 4;
  f.data = {0xCA, 0xFE, 0xBA, 0xBE};
  const auto r = bus.send(f);
  ASSERT_EQ(r.status, CanStatus::ok) << r.message;
  const std::string out = candump.read_stdout(kWait);
  const auto rc = candump.wait(kWait);
  ASSERT_TRUE(rc.has_value()) << "candump did not exit after one frame; output: " << out;
  EXPECT_EQ(*rc, 0);
  EXPECT_NE(out.find("vcan0"), std::string::npos) << out;
  EXPECT_NE(out.find("321   [4]  CA FE BA BE"), std::string::npos) << out;
}

// (3) kernel filters drop non-matching ids (and the other identifier kind).
TEST(Vcan, KernelFilterDropsNonMatchingIds) {
  SocketCanBus bus("vcan0");
  const std::vector<CanFilter> only123{{0x123, 0x7FF, false}};
  ASSERT_TRUE(bus.set_filters(only123).ok());
  run_ok({"cansend", "vcan0", "321#01"});
  run_ok({"cansend", "vcan0", "00000123#03"});
  run_ok({"cansend", "vcan0", "123#02"});
  CanFrame f;
  auto r = bus.receive(f, kWait);
  ASSERT_EQ(r.status, CanStatus::ok) << r.message;
  // Sent last, received first: the two earlier frames never reached the socket.
  EXPECT_EQ(f.id, 0x123u);
  EXPECT_FALSE(f.extended);
  ASSERT_EQ(f.dlc, 1);
  EXPECT_EQ(f.data[0], 0x02);
  r = bus.receive(f, 200ms);
  EXPECT_EQ(r.status, CanStatus::timeout) << "unexpected frame " << to_cansend(f);
}

// (4) two adapters on vcan1: both directions, extended ids, no echo to the sender, and an
// error frame (bus-off) reported as such.
TEST(Vcan, TwoBusesOnVcan1) {
  SocketCanBus a("vcan1");
  SocketCanBus b("vcan1");
  CanFrame ext;
  ext.id = 0x1ABCDEF0;
  ext.extended = true;
  ext.dlc = 8;
  ext.data = {1, 2, 3, 4, 5, 6, 7, 8};
  ASSERT_TRUE(a.send(ext).ok());
  CanFrame got;
  auto r = b.receive(got, kWait);
  ASSERT_EQ(r.status, CanStatus::ok) << r.message;
  EXPECT_TRUE(same_content(got, ext)) << to_cansend(got);

  CanFrame empty;
  empty.id = 0x7FF;
  ASSERT_TRUE(b.send(empty).ok());
  r = a.receive(got, kWait);
  ASSERT_EQ(r.status, CanStatus::ok) << r.message;
  EXPECT_TRUE(same_content(got, empty)) << to_cansend(got);
  EXPECT_EQ(a.receive(got, 100ms).status, CanStatus::timeout) << "sender received its own frame";

  // An error frame as a CAN controller driver would report bus-off (written raw: the adapter's
  // send() only sends data frames).
  const int raw = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  ASSERT_GE(raw, 0) << std::strerror(errno);
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = static_cast<int>(if_nametoindex("vcan1"));
  ASSERT_EQ(::bind(raw, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0) << std::strerror(errno);
  can_frame err{};
  err.can_id = CAN_ERR_FLAG | CAN_ERR_BUSOFF;
  err.len = CAN_ERR_DLC;
  ASSERT_EQ(::write(raw, &err, sizeof err), static_cast<ssize_t>(sizeof err)) << std::strerror(errno);
  ::close(raw);
  r = b.receive(got, kWait);
  ASSERT_EQ(r.status, CanStatus::error_frame) << to_string(r.status) << " " << r.message;
  EXPECT_TRUE(decode_error_frame(got).bus_off);
  EXPECT_NE(r.message.find("bus-off"), std::string::npos) << r.message;
}

TEST(Vcan, OpenErrorsAreClear) {
  try {
    SocketCanBus bus("nosuch0");
    FAIL() << "opened nosuch0";
  } catch (const CanOpenError& e) {
    EXPECT_NE(std::string(e.what()).find("no such CAN interface"), std::string::npos) << e.what();
    EXPECT_EQ(e.error_number(), ENODEV);
  }
  try {
    SocketCanBus bus("lo");
    FAIL() << "bound to lo";
  } catch (const CanOpenError& e) {
    EXPECT_NE(std::string(e.what()).find("not a CAN interface"), std::string::npos) << e.what();
  }
}
