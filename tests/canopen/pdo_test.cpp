// canopen/pdo.h on the dictionary generated from config/swum.eds (node 5): the default mappings of
// docs/canopen.md packed to exact bytes both ways, CiA 301's remapping procedure done by od.write()
// as a master does it, synchronous TPDOs every n-th SYNC and acyclic (type 0), event-driven TPDOs
// with inhibit time and event timer (no burst after a stall), synchronous RPDOs applied only at
// SYNC, length errors, refused writes, not-valid PDOs, and no allocation on the per-frame paths.
#include "pdo.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "allocation_count.h"
#include "canopen_test_support.h"
#include "object_dictionary.h"

namespace swum::canopen {
namespace {

using test::bytes_of;
using test::frame;
using test::Frames;
using test::try_write;
using test::write;
using Status = Pdos::RpdoStatus;
using Bytes = std::vector<std::uint8_t>;

constexpr std::int64_t kMs = 1'000'000;
constexpr std::uint8_t kNode = 5;

class PdoTest : public ::testing::Test {
 protected:
  ObjectDictionary od{swum_eds_objects(), kNode};
  Pdos pdos{od, kNode};
  Frames out;

  std::uint32_t at(std::uint16_t index, std::uint8_t sub = 0) const { return od.u32(od.slot(index, sub)); }
  void set(std::uint16_t index, std::uint32_t raw) { od.set(od.slot(index, 0), raw); }
  // The frames sent on one identifier, in order.
  std::vector<Bytes> on(std::uint32_t id) const {
    std::vector<Bytes> payloads;
    for (const protocol::CanFrame& f : out.sent) {
      if (f.id == id) payloads.push_back(bytes_of(f));
    }
    return payloads;
  }
  // CiA 301 7.5.2.36/38's procedure, each step an SDO download a master would send: the PDO
  // made not valid, the mapping emptied, the entries written, their count, the PDO valid again.
  void remap(std::uint16_t communication, std::uint16_t mapping, std::uint32_t cob_id,
             std::initializer_list<std::uint32_t> entries) {
    write(od, communication, 1, cob_id | 0x80000000U, 4);
    write(od, mapping, 0, 0, 1);
    std::uint8_t sub = 0;
    for (const std::uint32_t e : entries) write(od, mapping, ++sub, e, 4);
    write(od, mapping, 0, sub, 1);
    write(od, communication, 1, cob_id, 4);
  }
  void set_type(std::uint16_t communication, std::uint8_t type) { write(od, communication, 2, type, 1); }
};

TEST_F(PdoTest, DefaultTpdosPackTheirObjectsLittleEndian) {
  set(0x6041, 0x0637);                               // statusword: operation enabled
  set(0x6061, 0xFF);                                 // modes of operation display: -1
  set(0x606C, static_cast<std::uint32_t>(-123456));  // velocity actual, µm/s
  set(0x6064, 0x01020304);                           // position actual, µm
  pdos.reset(0);
  pdos.poll(0, out);  // event-driven (type 255 by default): each sent once at the start
  ASSERT_EQ(out.sent.size(), 4U);
  EXPECT_EQ(on(0x185), (std::vector<Bytes>{{0x37, 0x06}}));
  EXPECT_EQ(on(0x285), (std::vector<Bytes>{{0x37, 0x06, 0xFF}}));
  EXPECT_EQ(on(0x385), (std::vector<Bytes>{{0x37, 0x06, 0xC0, 0x1D, 0xFE, 0xFF}}));
  EXPECT_EQ(on(0x485), (std::vector<Bytes>{{0x04, 0x03, 0x02, 0x01, 0xC0, 0x1D, 0xFE, 0xFF}}));
  for (const protocol::CanFrame& f : out.sent) EXPECT_FALSE(f.extended);
}

TEST_F(PdoTest, DefaultRpdosWriteTheirObjects) {
  EXPECT_EQ(pdos.receive(frame(0x205, {0x06, 0x00})), Status::applied);
  EXPECT_EQ(at(0x6040), 0x0006U);
  EXPECT_EQ(pdos.receive(frame(0x305, {0x0F, 0x00, 0x03})), Status::applied);
  EXPECT_EQ(at(0x6040), 0x000FU);
  EXPECT_EQ(od.i32(od.slot(0x6060, 0)), 3);
  EXPECT_EQ(pdos.receive(frame(0x405, {0x1F, 0x00, 0xE0, 0x93, 0x04, 0x00})), Status::applied);  // 300 mm/s
  EXPECT_EQ(at(0x6040), 0x001FU);
  EXPECT_EQ(od.i32(od.slot(0x60FF, 0)), 300000);
  EXPECT_EQ(pdos.receive(frame(0x405, {0x1F, 0x00, 0x20, 0x6C, 0xFB, 0xFF})), Status::applied);  // -300 mm/s
  EXPECT_EQ(od.i32(od.slot(0x60FF, 0)), -300000);
  // RPDO4: drive frequency 39.5 kHz (mHz) and amplitude 120 V (mV).
  EXPECT_EQ(pdos.receive(frame(0x505, {0xE0, 0xB8, 0x5A, 0x02, 0xC0, 0xD4, 0x01, 0x00})), Status::applied);
  EXPECT_EQ(at(0x2001), 39500000U);
  EXPECT_EQ(at(0x2002), 120000U);
  EXPECT_EQ(pdos.length_errors(), 0U);
  EXPECT_EQ(pdos.refused_writes(), 0U);
}

TEST_F(PdoTest, FramesOfNoRpdoAreNotRpdos) {
  EXPECT_EQ(pdos.receive(frame(0x185, {0x06, 0x00})), Status::not_rpdo);        // our own TPDO1
  EXPECT_EQ(pdos.receive(frame(0x206, {0x06, 0x00})), Status::not_rpdo);        // node 6's RPDO1
  EXPECT_EQ(pdos.receive(frame(0x205, {0x06, 0x00}, true)), Status::not_rpdo);  // 29-bit
  EXPECT_EQ(at(0x6040), 0U);
}

TEST_F(PdoTest, RemappedTpdoIsSentWithTheNewLayout) {
  pdos.reset(0);
  remap(0x1800, 0x1A00, 0x185, {0x606C0020, 0x60410010, 0x60610008});
  EXPECT_EQ(at(0x1A00, 0), 3U);
  set(0x606C, 300000);
  set(0x6041, 0x0237);
  set(0x6061, 3);
  pdos.poll(1 * kMs, out);
  EXPECT_EQ(on(0x185), (std::vector<Bytes>{{0xE0, 0x93, 0x04, 0x00, 0x37, 0x02, 0x03}}));
}

TEST_F(PdoTest, ATpdoBeingRemappedIsNotSent) {
  pdos.reset(0);
  write(od, 0x1800, 1, 0x80000185, 4);
  pdos.poll(0, out);
  EXPECT_TRUE(on(0x185).empty());
  // Steps of the procedure refused while the PDO is valid (the dictionary's rule, CiA 301).
  write(od, 0x1800, 1, 0x185, 4);
  EXPECT_EQ(try_write(od, 0x1A00, 0, 0, 1), SdoAbort::value_range);  // docs/canopen.md: 0x06090030
  write(od, 0x1800, 1, 0x80000185, 4);
  write(od, 0x1A00, 0, 0, 1);
  write(od, 0x1800, 1, 0x185, 4);  // valid with no object mapped: nothing to send
  pdos.poll(1 * kMs, out);
  EXPECT_TRUE(on(0x185).empty());
  EXPECT_EQ(pdos.mapping_errors(), 0U);
}

TEST_F(PdoTest, RemappedRpdoWritesTheNewLayout) {
  remap(0x1400, 0x1600, 0x205, {0x60FF0020, 0x60400010});
  EXPECT_EQ(pdos.receive(frame(0x205, {0x06, 0x00})), Status::length_error);  // the old layout
  EXPECT_EQ(pdos.receive(frame(0x205, {0xA0, 0x86, 0x01, 0x00, 0x0F, 0x00})), Status::applied);
  EXPECT_EQ(od.i32(od.slot(0x60FF, 0)), 100000);
  EXPECT_EQ(at(0x6040), 0x000FU);
  // And onto another identifier: the old one is no RPDO any more.
  remap(0x1400, 0x1600, 0x220, {0x60400010});
  EXPECT_EQ(pdos.receive(frame(0x205, {0x07, 0x00})), Status::not_rpdo);
  EXPECT_EQ(pdos.receive(frame(0x220, {0x07, 0x00})), Status::applied);
  EXPECT_EQ(at(0x6040), 0x0007U);
}

TEST_F(PdoTest, SynchronousTpdoEveryNthSyncSampledAtTheSync) {
  set_type(0x1800, 3);
  pdos.reset(0);
  pdos.poll(0, out);  // synchronous PDOs are not event-driven
  EXPECT_TRUE(on(0x185).empty());
  std::vector<Bytes> expected;
  for (std::uint16_t sync = 1; sync <= 9; ++sync) {
    set(0x6041, sync);
    pdos.on_sync(static_cast<std::uint8_t>(sync), out);
    if (sync % 3 == 0) expected.push_back({static_cast<std::uint8_t>(sync), 0x00});
  }
  EXPECT_EQ(on(0x185), expected);  // SYNC 3, 6, 9 with the statusword of that moment
}

TEST_F(PdoTest, SynchronousTpdoEverySync) {
  set_type(0x1803, 1);  // TPDO4
  pdos.reset(0);
  for (int sync = 0; sync < 4; ++sync) pdos.on_sync(0, out);
  EXPECT_EQ(on(0x485).size(), 4U);  // sent even though nothing changed
}

TEST_F(PdoTest, AcyclicSynchronousTpdoAtTheSyncAfterAChange) {
  set_type(0x1800, 0);
  pdos.reset(0);
  set(0x6041, 0x0250);
  pdos.on_sync(0, out);  // the first SYNC after the reset: sent
  pdos.on_sync(0, out);
  pdos.on_sync(0, out);
  set(0x6041, 0x0231);
  pdos.poll(5 * kMs, out);  // not event-driven: waits for the SYNC
  EXPECT_EQ(on(0x185).size(), 1U);
  pdos.on_sync(0, out);
  pdos.on_sync(0, out);
  EXPECT_EQ(on(0x185), (std::vector<Bytes>{{0x50, 0x02}, {0x31, 0x02}}));
}

TEST_F(PdoTest, EventDrivenTpdoOnChangeHonoursTheInhibitTime) {
  write(od, 0x1800, 1, 0x80000185, 4);
  write(od, 0x1800, 3, 50, 2);  // 5 ms (100 µs units); writable only while not valid
  write(od, 0x1800, 1, 0x185, 4);
  pdos.reset(0);
  pdos.poll(0, out);
  pdos.poll(1 * kMs, out);  // unchanged: nothing
  set(0x6041, 0x0001);
  pdos.poll(2 * kMs, out);  // changed, inhibited
  set(0x6041, 0x0002);
  pdos.poll(5 * kMs - 1, out);
  pdos.poll(5 * kMs, out);  // the latest value once the inhibit time has passed
  pdos.poll(6 * kMs, out);
  set(0x6041, 0x0003);
  pdos.poll(20 * kMs, out);
  EXPECT_EQ(on(0x185), (std::vector<Bytes>{{0x00, 0x00}, {0x02, 0x00}, {0x03, 0x00}}));
}

TEST_F(PdoTest, EventTimerSendsUnchangedValuesWithoutABurstAfterAStall) {
  write(od, 0x1801, 5, 20, 2);  // TPDO2 event timer 20 ms
  pdos.reset(0);
  std::vector<std::int64_t> sent_ms;
  auto poll = [&](std::int64_t t_ms) {
    const std::size_t before = on(0x285).size();
    pdos.poll(t_ms * kMs, out);
    if (on(0x285).size() != before) sent_ms.push_back(t_ms);
  };
  for (std::int64_t t = 0; t <= 50; ++t) poll(t);
  for (std::int64_t t = 200; t <= 230; ++t) poll(t);  // nothing polled from 50 to 200 ms
  EXPECT_EQ(sent_ms, (std::vector<std::int64_t>{0, 20, 40, 200, 220}));
  // A change restarts the timer from its transmission.
  set(0x6041, 0x0004);
  poll(225);
  for (std::int64_t t = 226; t <= 250; ++t) poll(t);
  EXPECT_EQ(sent_ms, (std::vector<std::int64_t>{0, 20, 40, 200, 220, 225, 245}));
}

TEST_F(PdoTest, SynchronousRpdoIsAppliedOnlyAtTheSync) {
  set_type(0x1400, 1);
  EXPECT_EQ(pdos.receive(frame(0x205, {0x06, 0x00})), Status::latched);
  EXPECT_EQ(pdos.receive(frame(0x205, {0x07, 0x00})), Status::latched);  // the last before SYNC wins
  EXPECT_EQ(at(0x6040), 0U);
  pdos.on_sync(1, out);
  EXPECT_EQ(at(0x6040), 7U);
  set(0x6040, 0x0042);
  pdos.on_sync(2, out);  // nothing latched: nothing written again
  EXPECT_EQ(at(0x6040), 0x0042U);
}

TEST_F(PdoTest, AtTheSyncRpdosAreWrittenBeforeTpdosAreSampled) {
  set_type(0x1400, 0);
  remap(0x1800, 0x1A00, 0x185, {0x60400010});  // TPDO1 reports the controlword
  set_type(0x1800, 1);
  pdos.reset(0);
  EXPECT_EQ(pdos.receive(frame(0x205, {0x0F, 0x00})), Status::latched);
  pdos.on_sync(0, out);
  EXPECT_EQ(on(0x185), (std::vector<Bytes>{{0x0F, 0x00}}));
}

TEST_F(PdoTest, ShortRpdosAreLengthErrorsLongOnesUseTheMappedBytes) {
  EXPECT_EQ(pdos.receive(frame(0x405, {0x0F, 0x00, 0xE0, 0x93})), Status::length_error);
  EXPECT_EQ(pdos.receive(frame(0x205, {})), Status::length_error);
  EXPECT_EQ(at(0x6040), 0U);
  EXPECT_EQ(od.i32(od.slot(0x60FF, 0)), 0);
  EXPECT_EQ(pdos.length_errors(), 2U);
  // 8 bytes for a 2-byte mapping: the first two are used (CiA 301 allows it).
  EXPECT_EQ(pdos.receive(frame(0x205, {0x06, 0x00, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xFF})), Status::applied);
  EXPECT_EQ(at(0x6040), 6U);
  // Synchronous: refused on receipt, nothing latched.
  set_type(0x1400, 1);
  EXPECT_EQ(pdos.receive(frame(0x205, {0x07})), Status::length_error);
  pdos.on_sync(0, out);
  EXPECT_EQ(at(0x6040), 6U);
  EXPECT_EQ(pdos.length_errors(), 3U);
}

TEST_F(PdoTest, AnOutOfRangeValueIsRefusedTheOthersAreWritten) {
  // RPDO3: controlword and a target velocity of 2 m/s, above 0x60FF's limit of 1 m/s.
  EXPECT_EQ(pdos.receive(frame(0x405, {0x0F, 0x00, 0x80, 0x84, 0x1E, 0x00})), Status::refused);
  EXPECT_EQ(at(0x6040), 0x000FU);
  EXPECT_EQ(od.i32(od.slot(0x60FF, 0)), 0);
  EXPECT_EQ(pdos.refused_writes(), 1U);
  EXPECT_EQ(pdos.length_errors(), 0U);
}

TEST_F(PdoTest, NotValidPdosAreNeitherReceivedNorSent) {
  write(od, 0x1400, 1, 0x80000205, 4);
  for (std::uint16_t c = 0x1800; c <= 0x1803; ++c) {
    write(od, c, 1, (0x180U + 0x100U * (c - 0x1800U) + kNode) | 0x80000000U, 4);
  }
  pdos.reset(0);
  EXPECT_EQ(pdos.receive(frame(0x205, {0x06, 0x00})), Status::not_rpdo);
  pdos.poll(0, out);
  for (std::uint16_t c = 0x1800; c <= 0x1803; ++c) set_type(c, 1);
  pdos.on_sync(0, out);
  EXPECT_TRUE(out.sent.empty());
  EXPECT_EQ(at(0x6040), 0U);
}

TEST_F(PdoTest, ResetClearsCountsLastSentAndLatchedRpdos) {
  set_type(0x1800, 2);
  set_type(0x1400, 1);
  pdos.reset(0);
  pdos.on_sync(0, out);  // one SYNC of two counted
  EXPECT_EQ(pdos.receive(frame(0x205, {0x06, 0x00})), Status::latched);
  pdos.reset(0);
  pdos.on_sync(0, out);  // the count starts over; the latched RPDO is gone
  EXPECT_TRUE(on(0x185).empty());
  EXPECT_EQ(at(0x6040), 0U);
  pdos.on_sync(0, out);
  EXPECT_EQ(on(0x185).size(), 1U);
  // Event-driven TPDOs are sent again after a reset though nothing changed.
  pdos.poll(0, out);
  const std::size_t before = on(0x285).size();
  pdos.poll(1 * kMs, out);
  EXPECT_EQ(on(0x285).size(), before);
  pdos.reset(2 * kMs);
  pdos.poll(2 * kMs, out);
  EXPECT_EQ(on(0x285).size(), before + 1);
}

TEST_F(PdoTest, PerFramePathsAllocateNothing) {
  set_type(0x1400, 1);
  set_type(0x1801, 1);
  out.sent.reserve(64);
  pdos.reset(0);
  const long before = swum::test::allocation_count();
  for (int k = 0; k < 8; ++k) {
    (void)pdos.receive(frame(0x205, {0x06, 0x00}));
    (void)pdos.receive(frame(0x405, {0x06, 0x00, 0x01, 0x00, 0x00, 0x00}));
    (void)pdos.receive(frame(0x505, {0x01}));
    pdos.on_sync(0, out);
    pdos.poll(k * kMs, out);
  }
  EXPECT_EQ(swum::test::allocation_count(), before);
  EXPECT_FALSE(out.sent.empty());
}

}  // namespace
}  // namespace swum::canopen
