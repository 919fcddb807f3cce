// swum-emu's millisecond option values (app/milliseconds: --modbus-*-ms).
#include "app/milliseconds.h"

#include <gtest/gtest.h>

#include <string>

#include "transports/modbus_server.h"  // kMaxTimeoutMs, the largest value the options take

namespace swum::emu {
namespace {

TEST(ParseMilliseconds, TakesWholeNumbersInRange) {
  int v = -1;
  EXPECT_EQ(parse_milliseconds("0", 0, 100, v), "");
  EXPECT_EQ(v, 0);
  EXPECT_EQ(parse_milliseconds("86400000", 1, kMaxTimeoutMs, v), "");
  EXPECT_EQ(v, 86'400'000);
}

TEST(ParseMilliseconds, RejectsNamingTheText) {
  for (const char* bad : {"", "abc", "1.5", "2e3", "500ms", " 5", "5 ", "+5", "0x10"}) {
    int v = 7;
    const std::string e = parse_milliseconds(bad, 0, 1000, v);
    EXPECT_NE(e.find(std::string("'") + bad + "' is not a whole number of milliseconds (0 to 1000 ms)"),
              std::string::npos)
        << bad << ": " << e;
    EXPECT_EQ(v, 7) << bad;
  }
  for (const char* bad : {"-1", "1001", "99999999999999999999"}) {
    int v = 7;
    const std::string e = parse_milliseconds(bad, 0, 1000, v);
    EXPECT_NE(e.find(std::string("'") + bad + "' is out of range"), std::string::npos) << bad << ": " << e;
    EXPECT_EQ(v, 7) << bad;
  }
  int v = 7;
  EXPECT_NE(parse_milliseconds("0", 1, 1000, v), "");
}

}  // namespace
}  // namespace swum::emu
