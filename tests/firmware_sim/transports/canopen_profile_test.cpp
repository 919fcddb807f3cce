// CanopenProfile (firmware_sim/transports/canopen_profile.h) called as the transport calls it:
// boot-up, NMT, SDO through to the drive request, RPDOs, EMCY on the drive's error code, the
// heartbeat consumer's comm loss, malformed frames counted, lockstep SYNC semantics. The CiA 301
// parts themselves are tested in tests/canopen; here, their wiring to the node.
#include "transports/canopen_profile.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <vector>

#include "core/lockstep_clock.h"

namespace swum::emu {
namespace {

io::CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  io::CanFrame f;
  f.id = id;
  f.dlc = static_cast<std::uint8_t>(bytes.size());
  std::size_t i = 0;
  for (const std::uint8_t b : bytes) f.data[i++] = b;
  return f;
}

class RecordingPort final : public CanNodePort {
 public:
  void send(const io::CanFrame& f) override { sent.push_back(f); }
  Reason submit(Command) override { return Reason::none; }
  std::vector<io::CanFrame> sent;
  // The frames with this identifier, in order.
  [[nodiscard]] std::vector<io::CanFrame> with_id(std::uint32_t id) const {
    std::vector<io::CanFrame> out;
    for (const auto& f : sent)
      if (f.id == id) out.push_back(f);
    return out;
  }
};

constexpr std::uint8_t kNode = 5;

struct Rig {
  SharedState shared;
  CanopenProfile profile{CanopenProfileConfig{kNode, AmplifierLimits{}, 100}, shared};
  RecordingPort port;
  std::int64_t now_ns = 1'000'000'000;
  CanRxResult rx(const io::CanFrame& f) { return profile.receive(f, CanRxTime{now_ns, now_ns}, port); }
  void periodic() { profile.send_periodic(now_ns, port); }
  // An expedited SDO download of `size` bytes (1, 2 or 4); returns the response.
  io::CanFrame download(std::uint16_t index, std::uint8_t sub, std::uint32_t value, int size) {
    const auto cs = static_cast<std::uint8_t>(0x23 | ((4 - size) << 2));
    port.sent.clear();
    rx(frame(0x600 + kNode, {cs, static_cast<std::uint8_t>(index & 0xFF), static_cast<std::uint8_t>(index >> 8), sub,
                             static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8),
                             static_cast<std::uint8_t>(value >> 16), static_cast<std::uint8_t>(value >> 24)}));
    EXPECT_EQ(port.sent.size(), 1U);
    return port.sent.empty() ? io::CanFrame{} : port.sent.back();
  }
  io::CanFrame upload(std::uint16_t index, std::uint8_t sub) {
    port.sent.clear();
    rx(frame(0x600 + kNode,
             {0x40, static_cast<std::uint8_t>(index & 0xFF), static_cast<std::uint8_t>(index >> 8), sub, 0, 0, 0, 0}));
    EXPECT_EQ(port.sent.size(), 1U);
    return port.sent.empty() ? io::CanFrame{} : port.sent.back();
  }
};

std::uint32_t abort_code(const io::CanFrame& f) {
  return f.data[0] != 0x80 ? 0U
                           : f.data[4] | f.data[5] << 8 | f.data[6] << 16 | static_cast<std::uint32_t>(f.data[7]) << 24;
}

TEST(CanopenProfile, BootsIntoPreOperationalWithABootUpMessageAndAHeartbeat) {
  Rig rig;
  EXPECT_EQ(rig.profile.nmt_state(), canopen::NmtState::initialising);
  rig.periodic();
  ASSERT_FALSE(rig.port.sent.empty());
  EXPECT_EQ(rig.port.sent.front().id, 0x700U + kNode);  // boot-up: 0x700+N, one byte 0x00
  EXPECT_EQ(rig.port.sent.front().dlc, 1);
  EXPECT_EQ(rig.port.sent.front().data[0], 0x00);
  EXPECT_EQ(rig.profile.nmt_state(), canopen::NmtState::pre_operational);
  rig.port.sent.clear();
  rig.now_ns += 100'000'000;  // --heartbeat-ms 100 (0x1017 at boot)
  rig.periodic();
  ASSERT_EQ(rig.port.with_id(0x700 + kNode).size(), 1U);
  EXPECT_EQ(rig.port.with_id(0x700 + kNode)[0].data[0], 0x7F);  // pre-operational
  EXPECT_EQ(rig.upload(0x1017, 0).data[4], 100);
}

TEST(CanopenProfile, NmtCommandsAndResetsFollowCia301) {
  Rig rig;
  rig.periodic();
  EXPECT_EQ(rig.rx(frame(0x000, {0x01, kNode})).status, CanRxStatus::accepted);
  EXPECT_EQ(rig.profile.nmt_state(), canopen::NmtState::operational);
  EXPECT_EQ(rig.rx(frame(0x000, {0x02, 0})).status, CanRxStatus::accepted);  // broadcast stop
  EXPECT_EQ(rig.profile.nmt_state(), canopen::NmtState::stopped);
  rig.port.sent.clear();
  rig.rx(frame(0x600 + kNode, {0x40, 0x00, 0x10, 0, 0, 0, 0, 0}));
  EXPECT_TRUE(rig.port.sent.empty()) << "stopped: no SDO (CiA 301 Table 83)";
  EXPECT_EQ(rig.rx(frame(0x000, {0x01, kNode + 1})).status, CanRxStatus::ignored);  // another node's
  EXPECT_EQ(rig.profile.nmt_state(), canopen::NmtState::stopped);
  // Reset node: the application objects back to their defaults, boot-up, pre-operational.
  rig.rx(frame(0x000, {0x80, kNode}));
  EXPECT_EQ(abort_code(rig.download(0x60FF, 0, 123456, 4)), 0U);
  rig.port.sent.clear();
  rig.rx(frame(0x000, {0x81, kNode}));
  ASSERT_EQ(rig.port.with_id(0x700 + kNode).size(), 1U);
  EXPECT_EQ(rig.profile.nmt_state(), canopen::NmtState::pre_operational);
  const io::CanFrame v = rig.upload(0x60FF, 0);
  EXPECT_EQ(v.data[4] | v.data[5] << 8, 0) << "reset node restores 0x60FF's default";
  EXPECT_EQ(rig.shared.drive_request.load().target_velocity_um_s, 0);
}

TEST(CanopenProfile, MalformedNmtAndSyncAreRefusedAndCounted) {
  Rig rig;
  rig.periodic();
  EXPECT_EQ(rig.rx(frame(0x000, {0x01})).status, CanRxStatus::refused);
  EXPECT_EQ(rig.rx(frame(0x000, {0x07, kNode})).status, CanRxStatus::refused);  // no such command
  EXPECT_EQ(rig.rx(frame(0x080, {1, 2})).status, CanRxStatus::refused);         // SYNC: DLC 0 or 1
  EXPECT_EQ(rig.profile.counters().malformed.load(), 3U);
  const io::CanFrame count = rig.upload(0x2052, 0);
  EXPECT_EQ(count.data[4], 3);
  EXPECT_EQ(rig.profile.nmt_state(), canopen::NmtState::pre_operational);
}

TEST(CanopenProfile, SdoWritesOfDriveObjectsReachTheDriveRequest) {
  Rig rig;
  rig.periodic();
  EXPECT_EQ(abort_code(rig.download(0x6060, 0, 3, 1)), 0U);
  EXPECT_EQ(abort_code(rig.download(0x60FF, 0, static_cast<std::uint32_t>(-300000), 4)), 0U);
  EXPECT_EQ(abort_code(rig.download(0x6040, 0, 0x06, 2)), 0U);
  const DriveRequest r = rig.shared.drive_request.load();
  EXPECT_TRUE(r.active);
  EXPECT_EQ(r.mode, 3);
  EXPECT_EQ(r.target_velocity_um_s, -300000);
  EXPECT_EQ(r.controlword, 0x06);
  // Modes the drive lacks, options it lacks, frequencies outside the amplifier: refused.
  EXPECT_EQ(abort_code(rig.download(0x6060, 0, 1, 1)), 0x06090030U);
  EXPECT_EQ(abort_code(rig.download(0x605A, 0, 3, 2)), 0x06090030U);
  EXPECT_EQ(abort_code(rig.download(0x2001, 0, 20'000'000, 4)), 0x06090032U);
  EXPECT_EQ(abort_code(rig.download(0x2001, 0, 60'000'000, 4)), 0x06090031U);
  EXPECT_EQ(rig.shared.drive_request.load().mode, 3);
  EXPECT_GE(rig.profile.counters().sdo_aborts.load(), 4U);
}

TEST(CanopenProfile, FaultResetEdgesAreCountedNotLevels) {
  Rig rig;
  rig.periodic();
  rig.download(0x6040, 0, 0x80, 2);
  rig.download(0x6040, 0, 0x80, 2);  // held high: no new edge
  rig.download(0x6040, 0, 0x00, 2);
  rig.download(0x6040, 0, 0x80, 2);
  EXPECT_EQ(rig.shared.drive_request.load().fault_reset_edges, 2U);
}

TEST(CanopenProfile, RpdoOneCarriesTheControlwordOnlyWhenOperational) {
  Rig rig;
  rig.periodic();
  EXPECT_EQ(rig.rx(frame(0x200 + kNode, {0x0F, 0x00})).status, CanRxStatus::ignored);  // pre-operational
  EXPECT_EQ(rig.shared.drive_request.load().controlword, 0);
  rig.rx(frame(0x000, {0x01, kNode}));
  EXPECT_EQ(rig.rx(frame(0x200 + kNode, {0x0F, 0x00})).status, CanRxStatus::accepted);
  EXPECT_EQ(rig.shared.drive_request.load().controlword, 0x0F);
  // Shorter than its mapping: not processed, EMCY 0x8210 (CiA 301), counted.
  rig.port.sent.clear();
  EXPECT_EQ(rig.rx(frame(0x200 + kNode, {0x06})).status, CanRxStatus::refused);
  const auto emcy = rig.port.with_id(0x80 + kNode);
  ASSERT_EQ(emcy.size(), 1U);
  EXPECT_EQ(emcy[0].data[0], 0x10);
  EXPECT_EQ(emcy[0].data[1], 0x82);
  EXPECT_EQ(rig.shared.drive_request.load().controlword, 0x0F);
  EXPECT_EQ(rig.profile.counters().pdo_length_errors.load(), 1U);
}

// On the wall clock the node's services run every transmit period (send_periodic) on the
// loop's latest snapshot.
TEST(CanopenProfile, TheDrivesErrorCodeRaisesAnEmcyAndItsClearingTheResetMessage) {
  Rig rig;
  rig.periodic();
  Telemetry t;
  t.cia402.error_code = 0x4310;
  t.cia402.statusword = 0x0218;
  rig.shared.telemetry.store(t);  // what the loop published
  rig.port.sent.clear();
  rig.periodic();
  auto emcy = rig.port.with_id(0x80 + kNode);
  ASSERT_EQ(emcy.size(), 1U);
  EXPECT_EQ(emcy[0].dlc, 8);
  EXPECT_EQ(emcy[0].data[0], 0x10);
  EXPECT_EQ(emcy[0].data[1], 0x43);
  EXPECT_NE(emcy[0].data[2] & 0x08, 0) << "error register: temperature";
  rig.periodic();  // the same code: no second EMCY
  EXPECT_EQ(rig.port.with_id(0x80 + kNode).size(), 1U);
  const io::CanFrame code = rig.upload(0x603F, 0);
  EXPECT_EQ(code.data[4] | code.data[5] << 8, 0x4310);
  const io::CanFrame history = rig.upload(0x1003, 1);
  EXPECT_EQ(history.data[4] | history.data[5] << 8, 0x4310);
  t.cia402.error_code = 0;
  rig.shared.telemetry.store(t);
  rig.port.sent.clear();
  rig.periodic();
  emcy = rig.port.with_id(0x80 + kNode);
  ASSERT_EQ(emcy.size(), 1U);
  EXPECT_EQ(emcy[0].data[0], 0x00);
  EXPECT_EQ(emcy[0].data[1], 0x00);
  EXPECT_EQ(emcy[0].data[2], 0x00) << "nothing left in force";
}

// CiA 301: the error register and history record an error in every NMT state; only the EMCY
// itself waits for a state that may send it.
TEST(CanopenProfile, AFaultWhileStoppedIsRecordedWithoutAnEmcy) {
  Rig rig;
  rig.periodic();
  rig.rx(frame(0x000, {0x02, kNode}));  // stopped
  Telemetry t;
  t.cia402.error_code = 0x4310;
  rig.shared.telemetry.store(t);
  rig.port.sent.clear();
  rig.periodic();
  EXPECT_TRUE(rig.port.with_id(0x80 + kNode).empty());
  rig.rx(frame(0x000, {0x80, kNode}));  // pre-operational: SDO again
  EXPECT_EQ(rig.upload(0x1001, 0).data[4], 0x09) << "generic + temperature";
  EXPECT_EQ(rig.upload(0x1003, 0).data[4], 1);
  const io::CanFrame history = rig.upload(0x1003, 1);
  EXPECT_EQ(history.data[4] | history.data[5] << 8, 0x4310);
}

// An RPDO too short for its mapping: EMCY 0x8210 once; the next one that fits clears it with the
// error reset EMCY, and 0x1001 keeps only what is still in force.
TEST(CanopenProfile, APdoLengthErrorIsClearedByTheNextPdoThatFits) {
  Rig rig;
  rig.periodic();
  rig.rx(frame(0x000, {0x01, kNode}));
  rig.port.sent.clear();
  rig.rx(frame(0x200 + kNode, {0x06}));
  rig.rx(frame(0x200 + kNode, {0x06}));  // still too short: no second EMCY
  auto emcy = rig.port.with_id(0x80 + kNode);
  ASSERT_EQ(emcy.size(), 1U);
  EXPECT_EQ(emcy[0].data[0] | emcy[0].data[1] << 8, 0x8210);
  EXPECT_EQ(emcy[0].data[2], 0x11) << "generic + communication";
  EXPECT_EQ(rig.profile.counters().pdo_length_errors.load(), 2U);
  rig.port.sent.clear();
  rig.rx(frame(0x200 + kNode, {0x06, 0x00}));
  emcy = rig.port.with_id(0x80 + kNode);
  ASSERT_EQ(emcy.size(), 1U);
  EXPECT_EQ(emcy[0].data[0] | emcy[0].data[1] << 8, 0x0000);
  EXPECT_EQ(emcy[0].data[2], 0x00);
  EXPECT_EQ(rig.upload(0x1001, 0).data[4], 0x00);
  EXPECT_EQ(rig.shared.drive_request.load().controlword, 0x06);
}

// A reset keeps the drive's event counters running (a counter set back would read as one more
// event) and is itself a CiA 402 0x6007 event (reset application / communication, NMT stopped).
TEST(CanopenProfile, NmtResetsAndStopAreConnectionAbortsAndKeepTheCounters) {
  Rig rig;
  rig.periodic();
  rig.download(0x6040, 0, 0x80, 2);
  rig.download(0x6040, 0, 0x00, 2);
  rig.download(0x6040, 0, 0x80, 2);
  EXPECT_EQ(rig.shared.drive_request.load().fault_reset_edges, 2U);
  EXPECT_EQ(rig.shared.drive_request.load().comm_loss_events, 0U);
  rig.rx(frame(0x000, {0x82, kNode}));  // reset communication
  EXPECT_EQ(rig.shared.drive_request.load().fault_reset_edges, 2U);
  EXPECT_EQ(rig.shared.drive_request.load().comm_loss_events, 1U);
  rig.rx(frame(0x000, {0x01, kNode}));
  rig.rx(frame(0x000, {0x02, kNode}));  // stopped
  EXPECT_EQ(rig.shared.drive_request.load().comm_loss_events, 2U);
  rig.rx(frame(0x000, {0x81, kNode}));  // reset node: the drive objects to their defaults too
  const DriveRequest r = rig.shared.drive_request.load();
  EXPECT_EQ(r.comm_loss_events, 3U);
  EXPECT_EQ(r.fault_reset_edges, 2U);
  EXPECT_EQ(r.controlword, 0);
  rig.download(0x6040, 0, 0x80, 2);  // an edge again after the reset (controlword 0 now)
  EXPECT_EQ(rig.shared.drive_request.load().fault_reset_edges, 3U);
}

// The drive sees an RPDO's objects together: one publication per frame.
TEST(CanopenProfile, AnRpdosObjectsReachTheDriveTogether) {
  Rig rig;
  rig.periodic();
  rig.rx(frame(0x000, {0x01, kNode}));
  // RPDO3 by default: controlword + target velocity (docs/canopen.md).
  const std::uint64_t before = rig.profile.request_publications();
  rig.rx(frame(0x400 + kNode, {0x0F, 0x00, 0xE0, 0x93, 0x04, 0x00}));  // 300000 um/s
  EXPECT_EQ(rig.profile.request_publications(), before + 1) << "two objects, one publication";
  const DriveRequest r = rig.shared.drive_request.load();
  EXPECT_EQ(r.controlword, 0x0F);
  EXPECT_EQ(r.target_velocity_um_s, 300000);
}

TEST(CanopenProfile, ResetsKeepTheDrivesEventCounters) {
  // The drive reacts to a change of these counts: back at 0 after an NMT reset they would read
  // as a fault reset edge (or a heartbeat loss) no master sent.
  Rig rig;
  rig.periodic();
  rig.download(0x6040, 0, 0x80, 2);
  EXPECT_EQ(rig.shared.drive_request.load().fault_reset_edges, 1U);
  for (const std::uint8_t reset : {0x82, 0x81}) {  // reset communication, reset node
    rig.rx(frame(0x000, {reset, kNode}));
    EXPECT_EQ(rig.shared.drive_request.load().fault_reset_edges, 1U) << int(reset);
  }
}

TEST(CanopenProfile, ALostConsumedHeartbeatRaisesTheDrivesCommLossOnce) {
  Rig rig;
  rig.periodic();
  EXPECT_EQ(abort_code(rig.download(0x1016, 1, (0x7FU << 16) | 200, 4)), 0U);  // node 127, 200 ms
  rig.rx(frame(0x77F, {0x05}));  // monitoring starts with the first heartbeat
  rig.now_ns += 150'000'000;
  rig.periodic();
  EXPECT_EQ(rig.shared.drive_request.load().comm_loss_events, 0U);
  rig.now_ns += 100'000'000;
  rig.periodic();
  EXPECT_EQ(rig.shared.drive_request.load().comm_loss_events, 1U);
  rig.now_ns += 500'000'000;
  rig.periodic();
  EXPECT_EQ(rig.shared.drive_request.load().comm_loss_events, 1U) << "one loss, one event";
}

TEST(CanopenProfile, InLockstepEachTelemetryCallIsTheSyncOfSynchronousPdos) {
  Rig rig;
  LockstepClock clock;
  rig.shared.lockstep = &clock;
  rig.periodic();
  // TPDO1 synchronous (type 1): sent at every SYNC with the statusword sampled at it.
  EXPECT_EQ(abort_code(rig.download(0x1800, 2, 1, 1)), 0U);
  rig.rx(frame(0x000, {0x01, kNode}));
  Telemetry t;
  t.cia402.statusword = 0x0250;
  rig.port.sent.clear();
  rig.profile.send_telemetry(t, RejectSnapshot{}, rig.port);
  auto tpdo = rig.port.with_id(0x180 + kNode);
  ASSERT_EQ(tpdo.size(), 1U);
  EXPECT_EQ(tpdo[0].data[0] | tpdo[0].data[1] << 8, 0x0250);
  // A synchronous RPDO (type 1) written between SYNCs acts at the next SYNC only.
  EXPECT_EQ(abort_code(rig.download(0x1400, 2, 1, 1)), 0U);
  rig.rx(frame(0x200 + kNode, {0x07, 0x00}));
  EXPECT_EQ(rig.shared.drive_request.load().controlword, 0);
  rig.profile.send_telemetry(t, RejectSnapshot{}, rig.port);
  EXPECT_EQ(rig.shared.drive_request.load().controlword, 0x07);
}

}  // namespace
}  // namespace swum::emu

namespace swum::emu {
namespace {

// In lockstep the frames carry emulated time (standing still between SYNCs) beside their wall
// receive time: a segmented upload spread over transmit periods must not time out on the mix.
TEST(CanopenProfile, ASegmentedUploadInLockstepTimesOutOnTheWallClockOnly) {
  Rig rig;
  LockstepClock clock;
  rig.shared.lockstep = &clock;
  rig.periodic();
  auto rx_lockstep = [&](const io::CanFrame& f) {
    return rig.profile.receive(f, CanRxTime{rig.now_ns, 0}, rig.port);  // emulated time 0
  };
  rig.port.sent.clear();
  rx_lockstep(frame(0x600 + kNode, {0x40, 0x08, 0x10, 0, 0, 0, 0, 0}));
  std::uint8_t toggle = 0;
  for (int segment = 0; segment < 8; ++segment) {
    rig.now_ns += 10'000'000;  // a transmit period of wall time passes between two segments
    rig.periodic();
    rx_lockstep(frame(0x600 + kNode, {static_cast<std::uint8_t>(0x60 | toggle), 0, 0, 0, 0, 0, 0, 0}));
    toggle ^= 0x10;
  }
  const auto replies = rig.port.with_id(0x580 + kNode);
  ASSERT_EQ(replies.size(), 9U);  // initiate + 8 segments of the 53-byte name
  for (const auto& r : replies) EXPECT_NE(r.data[0], 0x80) << "no abort";
  EXPECT_NE(replies.back().data[0] & 0x01, 0) << "the last segment says so";
  // Idle for longer than the SDO timeout on the wall clock: the abort comes then.
  rx_lockstep(frame(0x600 + kNode, {0x40, 0x08, 0x10, 0, 0, 0, 0, 0}));
  rig.port.sent.clear();
  rig.now_ns += 2'000'000'000;
  rig.periodic();
  const auto aborts = rig.port.with_id(0x580 + kNode);
  ASSERT_EQ(aborts.size(), 1U);
  EXPECT_EQ(abort_code(aborts[0]), 0x05040000U);
}

}  // namespace
}  // namespace swum::emu

namespace swum::emu {
namespace {

bool lets_in(const CanopenProfile& profile, std::uint32_t id) {
  io::CanFrame f;
  f.id = id;
  return io::matches_any(profile.filters(), f);
}

// The kernel filters follow the dictionary: what the node acts on gets in, its own frames (the
// transport's receive socket gets them by loopback) never do.
TEST(CanopenProfile, ReceiveFiltersFollowTheRpdoIdentifiersAndConsumedHeartbeats) {
  Rig rig;
  rig.periodic();
  for (const std::uint32_t id :
       {0x000U, 0x080U, 0x600U + kNode, 0x200U + kNode, 0x300U + kNode, 0x400U + kNode, 0x500U + kNode})
    EXPECT_TRUE(lets_in(rig.profile, id)) << std::hex << id;
  for (const std::uint32_t id : {0x180U + kNode, 0x580U + kNode, 0x700U + kNode, 0x080U + kNode, 0x601U + kNode})
    EXPECT_FALSE(lets_in(rig.profile, id)) << std::hex << id;
  const std::uint64_t before = rig.profile.filters_generation();
  // RPDO1 moved to 0x2A0 by CiA 301's procedure: invalid, new identifier, valid.
  EXPECT_EQ(abort_code(rig.download(0x1400, 1, 0x80000200U + kNode, 4)), 0U);
  EXPECT_FALSE(lets_in(rig.profile, 0x200 + kNode));
  EXPECT_EQ(abort_code(rig.download(0x1400, 1, 0x800002A0U, 4)), 0U);
  EXPECT_EQ(abort_code(rig.download(0x1400, 1, 0x000002A0U, 4)), 0U);
  EXPECT_TRUE(lets_in(rig.profile, 0x2A0));
  EXPECT_EQ(abort_code(rig.download(0x1016, 2, (9U << 16) | 500, 4)), 0U);
  EXPECT_TRUE(lets_in(rig.profile, 0x709));
  EXPECT_GT(rig.profile.filters_generation(), before);
  // Reset communication: the defaults again.
  rig.rx(frame(0x000, {0x82, kNode}));
  EXPECT_TRUE(lets_in(rig.profile, 0x200 + kNode));
  EXPECT_FALSE(lets_in(rig.profile, 0x2A0));
  EXPECT_FALSE(lets_in(rig.profile, 0x709));
}

}  // namespace
}  // namespace swum::emu
