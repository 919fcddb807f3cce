// The one number formatter (src/formats/number_format.h) of src/ and host/ tables, labels and
// messages, and the shortest-decimal writer of swum-emu's trace rows, settings and recordings.
#include "formats/number_format.h"

#include <gtest/gtest.h>

#include <string>

namespace swum {
namespace {

TEST(NumberFormat, DefaultIsTheShortestFaithfulTableText) {
  EXPECT_EQ(format_number(40400.0), "40400");
  EXPECT_EQ(format_number(0.1 + 0.2), "0.3");
  EXPECT_EQ(format_number(1234567.0), "1.23457e+06");
}

TEST(NumberFormat, FormatIsAnyPrintfConversionOfOneDouble) {
  EXPECT_EQ(format_number(12.3456, "%.3f"), "12.346");
  EXPECT_EQ(format_number(-725.04, "%+.1f"), "-725.0");
  EXPECT_EQ(format_number(2.0, "%+.5g"), "+2");
}

TEST(NumberFormat, MessagesTakeUpToFourNumbers) {
  EXPECT_EQ(format_numbers("peak %.4g mm/s at %.0f Hz", 120.68, 40300.0), "peak 120.7 mm/s at 40300 Hz");
  EXPECT_EQ(format_numbers("%.0f/%.0f/%.0f/%.0f", 1.0, 2.0, 3.0, 4.0), "1/2/3/4");
}

// They were cut at 63 and 255 characters (the callers' old buffers): `swum control --speed-mm-s
// 1e60` printed a target with its last digits and unit missing.
TEST(NumberFormat, TextsAreNeverCut) {
  volatile double huge = 1e100;  // not a constant: no format-truncation warning
  const std::string digits = format_number(huge, "%.0f");
  EXPECT_EQ(digits.size(), 101u);
  EXPECT_EQ(digits.substr(0, 11), "10000000000");
  EXPECT_EQ(format_number(1e60, "%.6f"), format_number(1e60, "%.0f") + ".000000");
  EXPECT_EQ(format_numbers("%.0f%.0f%.0f", huge, huge, huge), digits + digits + digits);
  EXPECT_EQ(format_numbers("%.0f mm/s", huge), digits + " mm/s");
}

// The writer of swum-emu's trace rows and settings: the bytes golden traces hold.
TEST(NumberFormat, ShortestDecimalReadsBackAsTheSameDouble) {
  EXPECT_EQ(shortest_decimal(0.1), "0.1");
  EXPECT_EQ(shortest_decimal(40400.0), "40400");
  EXPECT_EQ(shortest_decimal(1e21), "1e+21");
  EXPECT_EQ(shortest_decimal(2.5e-7), "2.5e-07");
  EXPECT_EQ(shortest_decimal(-0.0), "-0");
  EXPECT_EQ(shortest_decimal(1.0 / 3.0), "0.3333333333333333");
  for (const double v : {1.0 / 3.0, 6.02214076e23, -1.5e-300, 1.7976931348623157e308}) {
    EXPECT_EQ(std::stod(shortest_decimal(v)), v);
  }
  std::string row = "a,";
  append_shortest_decimal(row, 12.5);
  EXPECT_EQ(row, "a,12.5");
}

TEST(PrintfString, ALineOfAnyLengthWithTextAndNumbers) {
  EXPECT_EQ(printf_string("  %-6s %d %.2f\n", "ab", 7, 1.5), "  ab     7 1.50\n");
  const std::string long_text(1000, 'n');
  const std::string line = printf_string("%s: %.6f\n", long_text.c_str(), 1e60);
  EXPECT_EQ(line.size(), 1000u + 2u + 67u + 1u);  // the double nearest 1e60 has 60 digits, then the point and six
  EXPECT_EQ(line.substr(0, 1000), long_text);
  EXPECT_EQ(line.back(), '\n');
}

}  // namespace
}  // namespace swum
