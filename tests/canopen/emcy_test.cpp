// canopen/emcy.h: the EMCY frame byte for byte, the error register bit of each class of code
// (CiA 301 7.5.2.2, Table 50), the pre-defined error field 0x1003 shifting (newest in sub 1, at
// most 8), the error reset, the inhibit time 0x1015 (one EMCY waits, a newer replaces it) and the
// COB-ID 0x1014 (bit 31: no EMCY) on the dictionary generated from config/swum.eds.
#include "emcy.h"

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "canopen_test_support.h"
#include "object_dictionary.h"

namespace swum::canopen {
namespace {

constexpr std::int64_t kMs = 1'000'000;
constexpr std::uint8_t kNode = 5;

using test::bytes_of;
using test::Frames;
using test::write;

class Emcy : public ::testing::Test {
 protected:
  ObjectDictionary od{swum_eds_objects(), kNode};
  EmcyProducer emcy{od};
  Frames out;

  std::uint32_t at(std::uint16_t index, std::uint8_t sub) const { return od.u32(od.slot(index, sub)); }
};

TEST(EmcyFrame, CodeRegisterAndManufacturerFieldInOrder) {
  const std::array<std::uint8_t, 5> manufacturer{0x01, 0x02, 0x03, 0x04, 0x05};
  const protocol::CanFrame f = emcy_frame(0x085, 0x4310, 0x09, manufacturer);
  EXPECT_EQ(f.id, 0x085U);
  EXPECT_FALSE(f.extended);
  EXPECT_EQ(bytes_of(f), (std::vector<std::uint8_t>{0x10, 0x43, 0x09, 0x01, 0x02, 0x03, 0x04, 0x05}));
  EXPECT_EQ(emcy_frame(0x7FFFFFFF, 0, 0, manufacturer).id, 0x7FFU);  // identifier bits 0-10 only
}

TEST(EmcyFrame, ErrorRegisterBitOfEachClass) {
  const std::vector<std::pair<std::uint16_t, std::uint8_t>> table{
      {0x0000, 0x00},  // error reset: no bit
      {0x1000, 0x01},  // generic
      {0x2320, 0x03},  // current (short circuit, output side)
      {0x3210, 0x05},  // voltage
      {0x4310, 0x09},  // temperature (excess drive temperature)
      {0x5000, 0x01},  // device hardware: generic only
      {0x6100, 0x01},  // internal software: generic only
      {0x7000, 0x01},  // additional modules
      {0x8100, 0x11},  // communication
      {0x8130, 0x11},  // heartbeat error
      {0x8210, 0x11},  // PDO length error (protocol error)
      {0x9000, 0x01},  // external error
      {0xF000, 0x01},  // additional functions
      {0xFF42, 0x81},  // device specific: manufacturer bit
  };
  for (const auto& [code, bits] : table) EXPECT_EQ(error_register_bits(code), bits) << std::hex << code;
}

TEST_F(Emcy, RaiseSendsTheFrameAndRecordsTheError) {
  emcy.raise(0x4310, 0, out);
  ASSERT_EQ(out.sent.size(), 1U);
  EXPECT_EQ(out.sent[0].id, 0x085U);
  EXPECT_EQ(bytes_of(out.sent[0]), (std::vector<std::uint8_t>{0x10, 0x43, 0x09, 0, 0, 0, 0, 0}));
  EXPECT_EQ(at(0x1001, 0), 0x09U);
  EXPECT_EQ(at(0x1003, 0), 1U);
  EXPECT_EQ(at(0x1003, 1), 0x4310U);
  EXPECT_EQ(at(0x1003, 2), 0U);
  EXPECT_EQ(emcy.sent(), 1U);
}

TEST_F(Emcy, RegisterBitsAccumulateUntilCleared) {
  emcy.raise(0x4310, 0, out);
  emcy.raise(0x2320, 1 * kMs, out);
  ASSERT_EQ(out.sent.size(), 2U);
  EXPECT_EQ(bytes_of(out.sent[1]), (std::vector<std::uint8_t>{0x20, 0x23, 0x0B, 0, 0, 0, 0, 0}));
  EXPECT_EQ(at(0x1001, 0), 0x0BU);
  emcy.clear(2 * kMs, out);
  ASSERT_EQ(out.sent.size(), 3U);
  EXPECT_EQ(bytes_of(out.sent[2]), (std::vector<std::uint8_t>{0x00, 0x00, 0x00, 0, 0, 0, 0, 0}));
  EXPECT_EQ(at(0x1001, 0), 0U);
  // The history stays after the error reset.
  EXPECT_EQ(at(0x1003, 0), 2U);
  EXPECT_EQ(at(0x1003, 1), 0x2320U);
  EXPECT_EQ(at(0x1003, 2), 0x4310U);
}

TEST_F(Emcy, HistoryKeepsTheNewestEightNewestFirst) {
  for (std::uint16_t k = 1; k <= 11; ++k) {
    emcy.raise(static_cast<std::uint16_t>(0x1000 + k), k * kMs, out);
    EXPECT_EQ(at(0x1003, 0), std::min<std::uint32_t>(k, 8U));
  }
  for (std::uint8_t sub = 1; sub <= 8; ++sub) EXPECT_EQ(at(0x1003, sub), 0x1000U + 12 - sub) << int(sub);
}

TEST_F(Emcy, AMasterClearsTheHistoryAndItStartsAgain) {
  emcy.raise(0x4310, 0, out);
  emcy.raise(0x2320, 0, out);
  write(od, 0x1003, 0, 0, 1);
  EXPECT_EQ(at(0x1003, 0), 0U);
  EXPECT_EQ(at(0x1003, 1), 0U);
  EXPECT_EQ(at(0x1003, 2), 0U);
  emcy.raise(0x8130, 0, out);
  EXPECT_EQ(at(0x1003, 0), 1U);
  EXPECT_EQ(at(0x1003, 1), 0x8130U);
  EXPECT_EQ(at(0x1003, 2), 0U);
}

TEST_F(Emcy, InhibitTimeHoldsTheNextOneAndTheNewestWaitingWins) {
  write(od, 0x1015, 0, 100, 2);  // 100 × 100 µs = 10 ms
  emcy.raise(0x4310, 0, out);
  ASSERT_EQ(out.sent.size(), 1U);
  emcy.raise(0x2320, 3 * kMs, out);
  EXPECT_EQ(out.sent.size(), 1U);
  EXPECT_TRUE(emcy.waiting());
  emcy.raise(0x8130, 4 * kMs, out);  // replaces 0x2320 (which stays in 0x1003)
  EXPECT_EQ(emcy.replaced(), 1U);
  emcy.poll(10 * kMs - 1, out);
  EXPECT_EQ(out.sent.size(), 1U);
  emcy.poll(10 * kMs, out);
  ASSERT_EQ(out.sent.size(), 2U);
  EXPECT_EQ(bytes_of(out.sent[1]), (std::vector<std::uint8_t>{0x30, 0x81, 0x1B, 0, 0, 0, 0, 0}));
  EXPECT_FALSE(emcy.waiting());
  emcy.poll(30 * kMs, out);
  EXPECT_EQ(out.sent.size(), 2U);
  // The inhibit time counts from the frame sent at 10 ms.
  emcy.clear(19 * kMs, out);
  EXPECT_EQ(out.sent.size(), 2U);
  emcy.poll(20 * kMs, out);
  ASSERT_EQ(out.sent.size(), 3U);
  EXPECT_EQ(bytes_of(out.sent[2]), (std::vector<std::uint8_t>{0, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(at(0x1003, 0), 3U);
}

TEST_F(Emcy, ResetDropsTheWaitingOneAndRestartsTheInhibitTime) {
  write(od, 0x1015, 0, 100, 2);
  emcy.raise(0x4310, 0, out);
  emcy.raise(0x2320, 1 * kMs, out);
  emcy.reset();
  emcy.poll(50 * kMs, out);
  EXPECT_EQ(out.sent.size(), 1U);
  emcy.raise(0x8130, 51 * kMs, out);
  emcy.raise(0x8130, 52 * kMs, out);
  EXPECT_EQ(out.sent.size(), 2U);
}

TEST_F(Emcy, ACobIdWithBit31SendsNothingButTheDictionaryRecords) {
  write(od, 0x1014, 0, 0x80000085, 4);
  emcy.raise(0x4310, 0, out);
  emcy.clear(1 * kMs, out);
  emcy.raise(0x2320, 2 * kMs, out);
  EXPECT_TRUE(out.sent.empty());
  EXPECT_EQ(at(0x1001, 0), 0x03U);
  EXPECT_EQ(at(0x1003, 0), 2U);
  write(od, 0x1014, 0, 0x000000A5, 4);  // valid again, on another identifier
  emcy.raise(0x4310, 3 * kMs, out);
  ASSERT_EQ(out.sent.size(), 1U);
  EXPECT_EQ(out.sent[0].id, 0x0A5U);
}

}  // namespace
}  // namespace swum::canopen
