// canopen/object_dictionary: lookup, defaults (node-relative ones too), typed values, every abort
// of write() and read(), the CiA 301 rules of the communication objects (0x1003, 0x1005, 0x1014,
// 0x1016, the PDO communication and mapping parameters), the mapping procedure, and the resets.
#include "object_dictionary.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "sdo_abort_print.h"

namespace swum::canopen {
namespace {

constexpr std::uint8_t kNode = 5;

// A master's write of `value`'s low `size` bytes, little-endian, as an SDO or RPDO carries it.
SdoAbort write(ObjectDictionary& od, std::uint16_t index, std::uint8_t sub, std::uint32_t value, std::size_t size) {
  std::array<std::uint8_t, 4> bytes{};
  for (std::size_t i = 0; i < 4; ++i) bytes[i] = static_cast<std::uint8_t>(value >> (8 * i));
  return od.write(od.slot(index, sub), std::span<const std::uint8_t>(bytes.data(), size));
}

std::uint32_t u32(const ObjectDictionary& od, std::uint16_t index, std::uint8_t sub) {
  return od.u32(od.slot(index, sub));
}

// Steps 1 and 2 of CiA 301's mapping procedure: the PDO invalidated, its mapping disabled.
void open_mapping(ObjectDictionary& od, std::uint16_t communication) {
  const std::uint32_t cob_id = u32(od, communication, 1);
  ASSERT_EQ(write(od, communication, 1, cob_id | 0x80000000u, 4), SdoAbort::none);
  ASSERT_EQ(write(od, static_cast<std::uint16_t>(communication + 0x200), 0, 0, 1), SdoAbort::none);
}

class SwumDictionary : public ::testing::Test {
 protected:
  ObjectDictionary od{swum_eds_objects(), kNode};
};

TEST_F(SwumDictionary, FindsTheObjectsOfTheEdsAndNothingElse) {
  EXPECT_EQ(od.size(), swum_eds_objects().size());
  ASSERT_TRUE(od.find(0x1018, 4));
  EXPECT_EQ(od.description(*od.find(0x1018, 4)).index, 0x1018);
  EXPECT_EQ(od.description(*od.find(0x1018, 4)).sub, 4);
  EXPECT_FALSE(od.find(0x1018, 5));  // the identity has sub-indexes 0-4
  EXPECT_FALSE(od.find(0x1800, 4));  // TPDO communication: sub 4 is reserved (CiA 301 7.5.2.37)
  EXPECT_TRUE(od.find(0x1800, 5));
  EXPECT_FALSE(od.find(0x1002, 0));
  EXPECT_FALSE(od.find(0x0000, 0));
  EXPECT_FALSE(od.find(0xFFFF, 0xFF));
  EXPECT_TRUE(od.has_index(0x6502));
  EXPECT_FALSE(od.has_index(0x6503));
  EXPECT_EQ(od.slot(0x1000, 0), 0u);             // the first object
  EXPECT_EQ(od.slot(0x6502, 0), od.size() - 1);  // the last
  EXPECT_THROW((void)od.slot(0x1234, 0), std::out_of_range);
  EXPECT_THROW((void)od.slot(0x1018, 9), std::out_of_range);
}

TEST_F(SwumDictionary, DefaultsComeFromTheEdsWithTheNodeIdAdded) {
  EXPECT_EQ(u32(od, 0x1000, 0), 0x00020192u);  // CiA 402 drive
  EXPECT_EQ(u32(od, 0x1005, 0), 0x80u);
  EXPECT_EQ(u32(od, 0x1014, 0), 0x80u + kNode);
  EXPECT_EQ(u32(od, 0x1017, 0), 1000u);
  EXPECT_EQ(u32(od, 0x1018, 2), 0x5357554Du);
  EXPECT_EQ(u32(od, 0x1018, 4), kNode);  // serial number: the node id
  EXPECT_EQ(u32(od, 0x1200, 1), 0x600u + kNode);
  EXPECT_EQ(u32(od, 0x1200, 2), 0x580u + kNode);
  EXPECT_EQ(u32(od, 0x1400, 1), 0x200u + kNode);
  EXPECT_EQ(u32(od, 0x1403, 1), 0x500u + kNode);
  EXPECT_EQ(u32(od, 0x1803, 1), 0x480u + kNode);
  EXPECT_EQ(u32(od, 0x1800, 2), 255u);
  EXPECT_EQ(u32(od, 0x1601, 0), 2u);
  EXPECT_EQ(u32(od, 0x1601, 2), 0x60600008u);
  EXPECT_EQ(u32(od, 0x1A03, 1), 0x60640020u);
  EXPECT_EQ(u32(od, 0x1A03, 3), 0u);
  EXPECT_EQ(u32(od, 0x6502, 0), 0x00010004u);
  EXPECT_EQ(od.i32(od.slot(0x2003, 0)), 9000);
  EXPECT_EQ(od.i32(od.slot(0x2031, 0)), 1500);
  EXPECT_EQ(od.i32(od.slot(0x605A, 0)), 2);
  EXPECT_EQ(u32(od, 0x2001, 0), 40000000u);

  ObjectDictionary other(swum_eds_objects(), 127);
  EXPECT_EQ(u32(other, 0x1800, 1), 0x1FFu);
  EXPECT_EQ(u32(other, 0x1014, 0), 0xFFu);
}

TEST_F(SwumDictionary, TypedValuesAreSignExtendedAndCutToTheirSize) {
  const std::size_t mode = od.slot(0x6060, 0);  // INTEGER8
  od.set(mode, 0xFF);
  EXPECT_EQ(od.i32(mode), -1);
  EXPECT_EQ(od.u32(mode), 0xFFu);
  od.set(mode, 0x1FD);  // the bits above the type are dropped
  EXPECT_EQ(od.u32(mode), 0xFDu);
  EXPECT_EQ(od.i32(mode), -3);
  const std::size_t phase = od.slot(0x2003, 0);  // INTEGER16
  od.set(phase, static_cast<std::uint16_t>(-18000));
  EXPECT_EQ(od.i32(phase), -18000);
  const std::size_t velocity = od.slot(0x60FF, 0);  // INTEGER32
  od.set(velocity, static_cast<std::uint32_t>(-300000));
  EXPECT_EQ(od.i32(velocity), -300000);
  const std::size_t controlword = od.slot(0x6040, 0);  // UNSIGNED16: no sign
  od.set(controlword, 0xFFFF);
  EXPECT_EQ(od.i32(controlword), 0xFFFF);
  EXPECT_EQ(od.string(od.slot(0x1008, 0)), "swum-emu bimodal standing-wave ultrasonic motor drive");
  EXPECT_EQ(od.string(od.slot(0x1009, 0)), "virtual");
  EXPECT_EQ(od.string(controlword), "");
}

TEST_F(SwumDictionary, ReadGivesTheLittleEndianBytesOfTheType) {
  std::array<std::uint8_t, 4> out{};
  std::size_t length = 99;
  ASSERT_EQ(od.read(od.slot(0x1000, 0), out, length), SdoAbort::none);
  EXPECT_EQ(length, 4u);
  EXPECT_EQ(out, (std::array<std::uint8_t, 4>{0x92, 0x01, 0x02, 0x00}));
  out = {};
  od.set(od.slot(0x6060, 0), 0xFF);
  ASSERT_EQ(od.read(od.slot(0x6060, 0), out, length), SdoAbort::none);
  EXPECT_EQ(length, 1u);
  EXPECT_EQ(out[0], 0xFF);
  ASSERT_EQ(od.read(od.slot(0x1017, 0), out, length), SdoAbort::none);
  EXPECT_EQ(length, 2u);
  EXPECT_EQ(out[0], 0xE8);  // 1000
  EXPECT_EQ(out[1], 0x03);
  // A string longer than 4 bytes does not fit an expedited read: read_string gives all of it.
  EXPECT_EQ(od.read(od.slot(0x1008, 0), out, length), SdoAbort::length_too_high);
  EXPECT_EQ(length, 0u);
  std::string_view text;
  ASSERT_EQ(od.read_string(od.slot(0x100A, 0), text), SdoAbort::none);
  EXPECT_EQ(text, "0.1.0");
  EXPECT_EQ(od.read_string(od.slot(0x1000, 0), text), SdoAbort::general_incompatibility);
  EXPECT_TRUE(text.empty());
}

TEST_F(SwumDictionary, WriteChecksAccessLengthAndLimits) {
  EXPECT_EQ(write(od, 0x1000, 0, 1, 4), SdoAbort::read_only);     // ro
  EXPECT_EQ(write(od, 0x1008, 0, 0x41, 1), SdoAbort::read_only);  // const string
  EXPECT_EQ(write(od, 0x6041, 0, 0, 2), SdoAbort::read_only);
  EXPECT_EQ(write(od, 0x6040, 0, 0x0F, 3), SdoAbort::length_too_high);
  EXPECT_EQ(write(od, 0x6040, 0, 0x0F, 1), SdoAbort::length_too_low);
  EXPECT_EQ(write(od, 0x6060, 0, 3, 4), SdoAbort::length_too_high);
  EXPECT_EQ(write(od, 0x60FF, 0, 1000001, 4), SdoAbort::value_too_high);
  EXPECT_EQ(write(od, 0x60FF, 0, static_cast<std::uint32_t>(-1000001), 4), SdoAbort::value_too_low);
  EXPECT_EQ(write(od, 0x6083, 0, 0, 4), SdoAbort::value_too_low);
  EXPECT_EQ(write(od, 0x6083, 0, 100000001, 4), SdoAbort::value_too_high);
  EXPECT_EQ(write(od, 0x2003, 0, static_cast<std::uint16_t>(-18001), 2), SdoAbort::value_too_low);
  EXPECT_EQ(write(od, 0x6060, 0, static_cast<std::uint8_t>(-2), 1), SdoAbort::value_too_low);
  EXPECT_EQ(u32(od, 0x60FF, 0), 0u);  // nothing refused was stored
  EXPECT_EQ(u32(od, 0x6083, 0), 2000000u);

  EXPECT_EQ(write(od, 0x60FF, 0, static_cast<std::uint32_t>(-1000000), 4), SdoAbort::none);  // the limit itself
  EXPECT_EQ(od.i32(od.slot(0x60FF, 0)), -1000000);
  EXPECT_EQ(write(od, 0x6040, 0, 0x000F, 2), SdoAbort::none);
  EXPECT_EQ(u32(od, 0x6040, 0), 0x000Fu);
  EXPECT_EQ(write(od, 0x6060, 0, static_cast<std::uint8_t>(-1), 1), SdoAbort::none);
  EXPECT_EQ(od.i32(od.slot(0x6060, 0)), -1);
}

struct RecordingObserver final : WriteObserver {
  SdoAbort veto = SdoAbort::none;
  std::vector<std::pair<std::size_t, std::uint32_t>> checked;
  std::vector<std::size_t> written_slots;
  SdoAbort check(std::size_t slot, std::uint32_t raw) override {
    checked.emplace_back(slot, raw);
    return veto;
  }
  void written(std::size_t slot) override { written_slots.push_back(slot); }
};

TEST_F(SwumDictionary, TheObserverVetoesAfterTheDictionarysOwnChecksAndHearsOfEachWrite) {
  RecordingObserver observer;
  od.set_observer(&observer);
  const std::size_t mode = od.slot(0x6060, 0);
  observer.veto = SdoAbort::value_range;  // e.g. mode 1 is no mode of this drive
  EXPECT_EQ(write(od, 0x6060, 0, 1, 1), SdoAbort::value_range);
  EXPECT_EQ(od.u32(mode), 0u);
  EXPECT_TRUE(observer.written_slots.empty());
  ASSERT_EQ(observer.checked.size(), 1u);
  EXPECT_EQ(observer.checked[0], std::make_pair(mode, std::uint32_t{1}));
  // A write the dictionary refuses never reaches the observer.
  EXPECT_EQ(write(od, 0x6060, 0, 4, 1), SdoAbort::value_too_high);
  EXPECT_EQ(observer.checked.size(), 1u);
  observer.veto = SdoAbort::none;
  EXPECT_EQ(write(od, 0x6060, 0, 3, 1), SdoAbort::none);
  EXPECT_EQ(od.u32(mode), 3u);
  EXPECT_EQ(observer.written_slots, std::vector<std::size_t>{mode});
  // The application's own set() passes neither.
  od.set(mode, 0);
  EXPECT_EQ(observer.checked.size(), 2u);
  EXPECT_EQ(observer.written_slots.size(), 1u);
  od.set_observer(nullptr);
  EXPECT_EQ(write(od, 0x6060, 0, 3, 1), SdoAbort::none);
  EXPECT_EQ(observer.written_slots.size(), 1u);
}

TEST_F(SwumDictionary, ErrorHistoryIsClearedByWritingZeroAndOnlyZero) {
  od.set(od.slot(0x1003, 0), 2);
  od.set(od.slot(0x1003, 1), 0x00004310);
  od.set(od.slot(0x1003, 2), 0x00008130);
  EXPECT_EQ(write(od, 0x1003, 0, 1, 1), SdoAbort::value_range);  // CiA 301 7.5.2.4
  EXPECT_EQ(u32(od, 0x1003, 1), 0x4310u);
  EXPECT_EQ(write(od, 0x1003, 1, 0, 4), SdoAbort::read_only);
  EXPECT_EQ(write(od, 0x1003, 0, 0, 1), SdoAbort::none);
  for (std::uint8_t sub = 0; sub <= 8; ++sub) EXPECT_EQ(u32(od, 0x1003, sub), 0u) << int{sub};
  EXPECT_EQ(u32(od, 0x1005, 0), 0x80u);  // the next object is untouched
}

TEST_F(SwumDictionary, SyncAndEmcyIdentifiersFollowCia301) {
  EXPECT_EQ(write(od, 0x1005, 0, 0x40000080, 4), SdoAbort::value_range);  // produce SYNC: not here
  EXPECT_EQ(write(od, 0x1005, 0, 0x20000080, 4), SdoAbort::value_range);  // 29-bit
  EXPECT_EQ(write(od, 0x1005, 0, 0x00000881, 4), SdoAbort::value_range);  // bits 11-28
  EXPECT_EQ(write(od, 0x1005, 0, 0x81, 4), SdoAbort::none);
  // EMCY: the identifier is fixed while the object exists (bit 31 clear).
  EXPECT_EQ(write(od, 0x1014, 0, 0x90, 4), SdoAbort::value_range);
  EXPECT_EQ(write(od, 0x1014, 0, 0x80000085, 4), SdoAbort::none);
  EXPECT_EQ(write(od, 0x1014, 0, 0x80000090, 4), SdoAbort::none);
  EXPECT_EQ(write(od, 0x1014, 0, 0x605, 4), SdoAbort::value_range);       // an SDO identifier (CiA 301 7.3.5)
  EXPECT_EQ(write(od, 0x1014, 0, 0xC0000090, 4), SdoAbort::value_range);  // bit 30 reserved
  EXPECT_EQ(write(od, 0x1014, 0, 0x90, 4), SdoAbort::none);
  EXPECT_EQ(u32(od, 0x1014, 0), 0x90u);
}

TEST_F(SwumDictionary, ConsumerHeartbeatEntriesWatchEachNodeOnce) {
  EXPECT_EQ(write(od, 0x1016, 1, 0x000A01F4, 4), SdoAbort::none);                     // node 10 every 500 ms
  EXPECT_EQ(write(od, 0x1016, 2, 0x000A03E8, 4), SdoAbort::general_incompatibility);  // node 10 again
  EXPECT_EQ(write(od, 0x1016, 2, 0x000A0000, 4), SdoAbort::none);                     // time 0: the entry is off
  EXPECT_EQ(write(od, 0x1016, 1, 0x000A03E8, 4), SdoAbort::none);                     // the same entry may change
  EXPECT_EQ(write(od, 0x1016, 3, 0x000B03E8, 4), SdoAbort::none);
  EXPECT_EQ(write(od, 0x1016, 4, 0x010B03E8, 4), SdoAbort::value_range);  // bits 24-31 reserved
  EXPECT_EQ(write(od, 0x1016, 4, 0x008003E8, 4), SdoAbort::value_range);  // node 128
  EXPECT_EQ(write(od, 0x1016, 0, 4, 1), SdoAbort::read_only);
}

TEST_F(SwumDictionary, PdoCommunicationParametersFollowCia301) {
  // COB-ID: fixed while the PDO exists; only 11-bit identifiers outside the restricted ones.
  EXPECT_EQ(write(od, 0x1800, 1, 0x190, 4), SdoAbort::value_range);
  EXPECT_EQ(write(od, 0x1800, 1, 0x185, 4), SdoAbort::none);       // no change
  EXPECT_EQ(write(od, 0x1800, 1, 0x40000185, 4), SdoAbort::none);  // bit 30 (no RTR) alone
  EXPECT_EQ(write(od, 0x1800, 1, 0x80000185, 4), SdoAbort::none);  // invalidate
  EXPECT_EQ(write(od, 0x1800, 1, 0x80000190, 4), SdoAbort::none);
  EXPECT_EQ(write(od, 0x1800, 1, 0xA0000190, 4), SdoAbort::value_range);  // 29-bit
  EXPECT_EQ(write(od, 0x1800, 1, 0x80010190, 4), SdoAbort::value_range);  // bits 11-28
  EXPECT_EQ(write(od, 0x1800, 1, 0x585, 4), SdoAbort::value_range);       // SDO response identifier
  EXPECT_EQ(write(od, 0x1800, 1, 0x701, 4), SdoAbort::value_range);       // heartbeat
  EXPECT_EQ(write(od, 0x1800, 1, 0x190, 4), SdoAbort::none);
  EXPECT_EQ(u32(od, 0x1800, 1), 0x190u);
  EXPECT_EQ(write(od, 0x1400, 1, 0x300, 4), SdoAbort::value_range);  // RPDO alike
  EXPECT_EQ(write(od, 0x1400, 0, 3, 1), SdoAbort::read_only);
  // Transmission type: 0-240 synchronous, 254/255 event-driven; 241-251 reserved, 252/253 RTR.
  for (std::uint32_t type : {0u, 1u, 240u, 254u, 255u}) EXPECT_EQ(write(od, 0x1801, 2, type, 1), SdoAbort::none);
  for (std::uint32_t type : {241u, 251u, 252u, 253u}) EXPECT_EQ(write(od, 0x1801, 2, type, 1), SdoAbort::value_range);
  for (std::uint32_t type : {241u, 253u}) EXPECT_EQ(write(od, 0x1401, 2, type, 1), SdoAbort::value_range);
  EXPECT_EQ(u32(od, 0x1801, 2), 255u);
  // Inhibit time: fixed while the PDO exists; the event timer is not.
  EXPECT_EQ(write(od, 0x1802, 3, 10, 2), SdoAbort::value_range);
  EXPECT_EQ(write(od, 0x1802, 5, 100, 2), SdoAbort::none);
  EXPECT_EQ(write(od, 0x1802, 1, 0x80000387, 4), SdoAbort::none);
  EXPECT_EQ(write(od, 0x1802, 3, 10, 2), SdoAbort::none);
  EXPECT_EQ(u32(od, 0x1802, 3), 10u);
}

TEST_F(SwumDictionary, TpdoRemappedByTheCia301Procedure) {
  // Out of order: the PDO is valid.
  EXPECT_EQ(write(od, 0x1A00, 0, 0, 1), SdoAbort::value_range);
  EXPECT_EQ(write(od, 0x1A00, 1, 0x606C0020, 4), SdoAbort::value_range);
  EXPECT_EQ(write(od, 0x1A00, 0, 1, 1), SdoAbort::none);  // the value already there: no change
  // 1. invalidate the PDO
  ASSERT_EQ(write(od, 0x1800, 1, 0x80000185, 4), SdoAbort::none);
  // entries only while the mapping is disabled
  EXPECT_EQ(write(od, 0x1A00, 1, 0x606C0020, 4), SdoAbort::value_range);
  // 2. disable the mapping
  ASSERT_EQ(write(od, 0x1A00, 0, 0, 1), SdoAbort::none);
  // 3. the entries
  ASSERT_EQ(write(od, 0x1A00, 1, 0x60410010, 4), SdoAbort::none);
  ASSERT_EQ(write(od, 0x1A00, 2, 0x606C0020, 4), SdoAbort::none);
  ASSERT_EQ(write(od, 0x1A00, 3, 0x20120010, 4), SdoAbort::none);
  // 4. enable the mapping
  ASSERT_EQ(write(od, 0x1A00, 0, 3, 1), SdoAbort::none);
  // 5. validate the PDO
  ASSERT_EQ(write(od, 0x1800, 1, 0x185, 4), SdoAbort::none);
  EXPECT_EQ(u32(od, 0x1A00, 0), 3u);
  EXPECT_EQ(u32(od, 0x1A00, 1), 0x60410010u);
  EXPECT_EQ(u32(od, 0x1A00, 2), 0x606C0020u);
  EXPECT_EQ(u32(od, 0x1A00, 3), 0x20120010u);
}

TEST_F(SwumDictionary, MappingEntriesAndCountsThatCannotBeAreRefused) {
  open_mapping(od, 0x1800);
  open_mapping(od, 0x1400);
  // step 3 (CiA 301: 0x06020000 or 0x06040041)
  EXPECT_EQ(write(od, 0x1A00, 1, 0x12340020, 4), SdoAbort::no_object);
  EXPECT_EQ(write(od, 0x1A00, 1, 0x10180920, 4), SdoAbort::no_object);     // 0x1018 has no sub 9
  EXPECT_EQ(write(od, 0x1A00, 1, 0x00070020, 4), SdoAbort::no_object);     // no dummy entries
  EXPECT_EQ(write(od, 0x1A00, 1, 0x10000020, 4), SdoAbort::not_mappable);  // device type: PDOMapping=0
  EXPECT_EQ(write(od, 0x1A00, 1, 0x10080000, 4), SdoAbort::not_mappable);  // a string
  EXPECT_EQ(write(od, 0x1600, 1, 0x60410010, 4), SdoAbort::not_mappable);  // RPDO into a read-only object
  EXPECT_EQ(write(od, 0x1A00, 1, 0x60410020, 4), SdoAbort::not_mappable);  // 32 bits of a 16-bit object
  EXPECT_EQ(write(od, 0x1A00, 1, 0x60410008, 4), SdoAbort::not_mappable);  // part of it
  EXPECT_EQ(write(od, 0x1A00, 1, 0x60400010, 4), SdoAbort::none);          // a TPDO may carry an rw object
  EXPECT_EQ(write(od, 0x1600, 1, 0x60FF0020, 4), SdoAbort::none);
  EXPECT_EQ(write(od, 0x1A00, 1, 0, 4), SdoAbort::none);  // an empty entry
  // step 4 (CiA 301: 0x06020000 or 0x06040042)
  EXPECT_EQ(write(od, 0x1A00, 0, 1, 1), SdoAbort::no_object);  // entry 1 is empty
  ASSERT_EQ(write(od, 0x1A00, 1, 0x606C0020, 4), SdoAbort::none);
  ASSERT_EQ(write(od, 0x1A00, 2, 0x60640020, 4), SdoAbort::none);
  ASSERT_EQ(write(od, 0x1A00, 3, 0x60410010, 4), SdoAbort::none);
  EXPECT_EQ(write(od, 0x1A00, 0, 3, 1), SdoAbort::pdo_too_long);  // 80 bits
  EXPECT_EQ(write(od, 0x1A00, 0, 9, 1), SdoAbort::pdo_too_long);
  EXPECT_EQ(write(od, 0x1A00, 0, 255, 1), SdoAbort::pdo_too_long);
  EXPECT_EQ(u32(od, 0x1A00, 0), 0u);
  EXPECT_EQ(write(od, 0x1A00, 0, 2, 1), SdoAbort::none);  // 64 bits
}

TEST_F(SwumDictionary, ResetsRestoreTheirOwnRangeOnly) {
  ASSERT_EQ(write(od, 0x1017, 0, 250, 2), SdoAbort::none);
  open_mapping(od, 0x1800);
  ASSERT_EQ(write(od, 0x6083, 0, 5000, 4), SdoAbort::none);
  ASSERT_EQ(write(od, 0x2003, 0, 100, 2), SdoAbort::none);
  od.set(od.slot(0x6041, 0), 0x0237);
  od.reset_communication();
  EXPECT_EQ(u32(od, 0x1017, 0), 1000u);
  EXPECT_EQ(u32(od, 0x1800, 1), 0x185u);
  EXPECT_EQ(u32(od, 0x1A00, 0), 1u);
  EXPECT_EQ(u32(od, 0x6083, 0), 5000u);
  EXPECT_EQ(u32(od, 0x2003, 0), 100u);
  od.reset_application();
  EXPECT_EQ(u32(od, 0x6083, 0), 2000000u);
  EXPECT_EQ(u32(od, 0x2003, 0), 9000u);
  EXPECT_EQ(u32(od, 0x6041, 0), 0u);
}

// Small tables for what the swum dictionary has none of.
constexpr ObjectDescription kSmall[] = {
    {0x2000, 0, "write only", DataType::unsigned16, Access::wo, true, 7, false, nullptr, false, 0, 0},
    {0x2001, 0, "flag", DataType::boolean, Access::rw, false, 0, false, nullptr, false, 0, 0},
    {0x2002, 0, "gain", DataType::real32, Access::rw, false, 0x3F800000, false, nullptr, false, 0, 0},
    {0x2003, 0, "short text", DataType::visible_string, Access::ro, false, 0, false, "abc", false, 0, 0},
};

TEST(SmallDictionary, WriteOnlyBooleanRealAndShortStringObjects) {
  ObjectDictionary od(kSmall, 1);
  std::array<std::uint8_t, 4> out{};
  std::size_t length = 9;
  EXPECT_EQ(od.read(0, out, length), SdoAbort::write_only);
  EXPECT_EQ(length, 0u);
  std::string_view text;
  EXPECT_EQ(od.read_string(0, text), SdoAbort::write_only);
  EXPECT_EQ(write(od, 0x2000, 0, 9, 2), SdoAbort::none);
  EXPECT_EQ(od.u32(0), 9u);
  EXPECT_EQ(write(od, 0x2001, 0, 2, 1), SdoAbort::value_range);
  EXPECT_EQ(write(od, 0x2001, 0, 1, 1), SdoAbort::none);
  EXPECT_EQ(write(od, 0x2002, 0, 0xC0490FDB, 4), SdoAbort::none);  // -pi: bits, no range
  EXPECT_EQ(od.u32(2), 0xC0490FDBu);
  ASSERT_EQ(od.read(3, out, length), SdoAbort::none);
  EXPECT_EQ(length, 3u);
  EXPECT_EQ(out[0], 'a');
  EXPECT_EQ(out[2], 'c');
  EXPECT_EQ(write(od, 0x2003, 0, 0x41, 1), SdoAbort::read_only);
}

TEST(SmallDictionary, ABadTableOrNodeIdIsRefusedAtLoad) {
  EXPECT_THROW(ObjectDictionary(kSmall, 0), std::invalid_argument);
  EXPECT_THROW(ObjectDictionary(kSmall, 128), std::invalid_argument);
  const ObjectDescription unsorted[] = {kSmall[1], kSmall[0]};
  EXPECT_THROW(ObjectDictionary(unsorted, 1), std::invalid_argument);
  const ObjectDescription twice[] = {kSmall[0], kSmall[0]};
  EXPECT_THROW(ObjectDictionary(twice, 1), std::invalid_argument);
  const ObjectDescription outside_limits[] = {
      {0x2000, 0, "x", DataType::integer8, Access::rw, false, 5, false, nullptr, true, -1, 3}};
  EXPECT_THROW(ObjectDictionary(outside_limits, 1), std::invalid_argument);
  const ObjectDescription limits_outside_type[] = {
      {0x2000, 0, "x", DataType::unsigned8, Access::rw, false, 0, false, nullptr, true, 0, 256}};
  EXPECT_THROW(ObjectDictionary(limits_outside_type, 1), std::invalid_argument);
  // A node-relative default is checked with the node id added.
  const ObjectDescription node_relative[] = {
      {0x2000, 0, "x", DataType::unsigned8, Access::rw, false, 0x80, true, nullptr, false, 0, 0}};
  EXPECT_NO_THROW(ObjectDictionary(node_relative, 127));
  const ObjectDescription node_relative_u8[] = {
      {0x2000, 0, "x", DataType::unsigned8, Access::rw, false, 0x81, true, nullptr, false, 0, 0}};
  EXPECT_THROW(ObjectDictionary(node_relative_u8, 127), std::invalid_argument);
  const ObjectDescription no_text[] = {
      {0x2000, 0, "x", DataType::visible_string, Access::ro, false, 0, false, nullptr, false, 0, 0}};
  EXPECT_THROW(ObjectDictionary(no_text, 1), std::invalid_argument);
  const ObjectDescription writable_text[] = {
      {0x2000, 0, "x", DataType::visible_string, Access::rw, false, 0, false, "t", false, 0, 0}};
  EXPECT_THROW(ObjectDictionary(writable_text, 1), std::invalid_argument);
}

}  // namespace
}  // namespace swum::canopen
