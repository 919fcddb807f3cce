// io/can_bus.h (and the frame type it carries, protocol/can_frame.h): validation, cansend notation, filter semantics,
// error-frame decoding.
#include <gtest/gtest.h>
#include <linux/can/error.h>

#include <array>
#include <string>

#include "can_bus.h"

using namespace swum::io;

TEST(CanFrame, ValidateAcceptsLimitsAndNamesWhatIsWrong) {
  CanFrame f;
  f.id = 0x7FF;
  f.dlc = 8;
  EXPECT_EQ(validate(f), "");
  f.id = 0x800;
  EXPECT_NE(validate(f).find("0x800 exceeds 0x7FF"), std::string::npos) << validate(f);
  f.extended = true;
  f.id = 0x1FFFFFFF;
  EXPECT_EQ(validate(f), "");
  f.id = 0x20000000;
  EXPECT_NE(validate(f).find("extended"), std::string::npos);
  f.id = 1;
  f.dlc = 9;
  EXPECT_NE(validate(f).find("dlc 9"), std::string::npos);
}

TEST(CanFrame, CansendNotationRoundTrips) {
  CanFrame f;
  ASSERT_EQ(parse_cansend("123#DEADBEEF", f), "");
  EXPECT_EQ(f.id, 0x123u);
  EXPECT_FALSE(f.extended);
  EXPECT_EQ(f.dlc, 4);
  EXPECT_EQ(f.data[0], 0xDE);
  EXPECT_EQ(f.data[3], 0xEF);
  EXPECT_EQ(to_cansend(f), "123#DEADBEEF");

  CanFrame e;
  ASSERT_EQ(parse_cansend("1ABCDEF0#00.11.22", e), "");
  EXPECT_TRUE(e.extended);
  EXPECT_EQ(e.id, 0x1ABCDEF0u);
  EXPECT_EQ(e.dlc, 3);
  EXPECT_EQ(to_cansend(e), "1ABCDEF0#001122");

  CanFrame empty;
  ASSERT_EQ(parse_cansend("7FF#", empty), "");
  EXPECT_EQ(empty.dlc, 0);
  EXPECT_EQ(to_cansend(empty), "7FF#");
}

// The allocation-free form (the --record-can recording) writes the same text and has room for
// any 32-bit identifier with eight bytes.
TEST(CanFrame, CansendIntoABufferIsTheSameTextAndBounded) {
  std::array<char, swum::protocol::kCansendMaxLength + 1> text{};
  CanFrame e{0x1ABCDEF0, true, 2, {0xDE, 0xAD}};
  EXPECT_EQ(std::string(text.data(), swum::protocol::to_cansend(e, text)), "1ABCDEF0#DEAD");
  CanFrame s{0x080, false, 0, {}};
  EXPECT_EQ(std::string(text.data(), swum::protocol::to_cansend(s, text)), "080#");
  CanFrame widest{0xFFFFFFFF, true, 8, {1, 2, 3, 4, 5, 6, 7, 8}};
  EXPECT_EQ(swum::protocol::to_cansend(widest, text), swum::protocol::kCansendMaxLength);
  EXPECT_STREQ(text.data(), "FFFFFFFF#0102030405060708");
}

TEST(CanFrame, CansendNotationRejectsBadInputClearly) {
  const CanFrame untouched{0x42, false, 1, {0x99}};
  auto error_of = [&](const char* text) {
    CanFrame f = untouched;
    const std::string err = parse_cansend(text, f);
    EXPECT_TRUE(same_content(f, untouched)) << text << ": a failed parse changed the frame";
    return err;
  };
  EXPECT_NE(error_of("123DEAD").find("no '#'"), std::string::npos);
  EXPECT_NE(error_of("12#00").find("3 (standard) or 8 (extended)"), std::string::npos);
  EXPECT_NE(error_of("1G3#00").find("not hexadecimal"), std::string::npos);
  EXPECT_NE(error_of("123#0").find("odd number"), std::string::npos);
  EXPECT_NE(error_of("123#001122334455667788").find("more than 8"), std::string::npos);
  EXPECT_NE(error_of("FFF#00").find("exceeds"), std::string::npos);
  EXPECT_EQ(error_of("FFF#00").rfind("bad CAN frame 'FFF#00': ", 0), 0u);
}

TEST(CanFrame, FiltersFollowKernelSemantics) {
  CanFrame f;
  f.id = 0x123;
  EXPECT_TRUE(matches(CanFilter{0x123, 0x7FF, false}, f));
  EXPECT_FALSE(matches(CanFilter{0x124, 0x7FF, false}, f));
  EXPECT_TRUE(matches(CanFilter{0x100, 0x700, false}, f));  // range 0x100..0x1FF
  EXPECT_FALSE(matches(CanFilter{0x123, 0x7FF, true}, f));  // kind must match
  f.extended = true;
  EXPECT_TRUE(matches(CanFilter{0x123, 0x1FFFFFFF, true}, f));
  EXPECT_FALSE(matches(CanFilter{0x123, 0x7FF, false}, f));
  std::vector<CanFilter> none;
  EXPECT_TRUE(matches_any(none, f));  // empty list accepts all
  std::vector<CanFilter> two{{0x1, 0x7FF, false}, {0x123, 0x1FFFFFFF, true}};
  EXPECT_TRUE(matches_any(two, f));
  EXPECT_NE(validate(CanFilter{0x800, 0x7FF, false}).find("exceeds"), std::string::npos);
}

TEST(CanFrame, ErrorFramesDecode) {
  CanFrame f;
  f.id = CAN_ERR_BUSOFF;
  f.dlc = 8;
  auto info = decode_error_frame(f);
  EXPECT_TRUE(info.bus_off);
  EXPECT_FALSE(info.error_passive);
  EXPECT_NE(info.describe().find("bus-off"), std::string::npos);

  f.id = CAN_ERR_CRTL | CAN_ERR_ACK;
  f.data[1] = CAN_ERR_CRTL_TX_PASSIVE;
  info = decode_error_frame(f);
  EXPECT_FALSE(info.bus_off);
  EXPECT_TRUE(info.error_passive);
  EXPECT_TRUE(info.no_ack);
  EXPECT_NE(info.describe().find("error-passive"), std::string::npos);
}

TEST(CanFrame, SameContentIgnoresTimestampAndUnusedBytes) {
  CanFrame a, b;
  a.id = b.id = 0x10;
  a.dlc = b.dlc = 2;
  a.data = {1, 2, 3};
  b.data = {1, 2, 9};
  b.timestamp = std::chrono::nanoseconds(5);
  EXPECT_TRUE(same_content(a, b));
  b.data[1] = 7;
  EXPECT_FALSE(same_content(a, b));
}
