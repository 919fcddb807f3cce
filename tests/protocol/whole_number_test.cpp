#include "whole_number.h"

#include <gtest/gtest.h>

#include <limits>

namespace swum::protocol {
namespace {

TEST(WholeNumber, ReadsTheWholeTextOnly) {
  EXPECT_EQ(parse_whole_number("1502", 0, 65535), 1502);
  EXPECT_EQ(parse_whole_number("0", 0, 65535), 0);
  EXPECT_EQ(parse_whole_number("-7", -10, 10), -7);
  for (const char* bad : {"", " 1502", "1502 ", "+1502", "15x", "1502.9", "1e3", "0x10", "--1", "-", "١٢"}) {
    EXPECT_EQ(parse_whole_number(bad, std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max()),
              std::nullopt)
        << "'" << bad << "'";
  }
}

TEST(WholeNumber, RangeIsInclusiveAndOverflowIsRefused) {
  EXPECT_EQ(parse_whole_number("65535", 0, 65535), 65535);
  EXPECT_EQ(parse_whole_number("65536", 0, 65535), std::nullopt);
  EXPECT_EQ(parse_whole_number("-1", 0, 65535), std::nullopt);
  EXPECT_EQ(parse_whole_number("99999999999999999999", 0, std::numeric_limits<long long>::max()), std::nullopt);
}

}  // namespace
}  // namespace swum::protocol
