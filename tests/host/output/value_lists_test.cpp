#include "output/value_lists.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace swum::host {
namespace {

TEST(ParseFiniteNumber, AcceptsPlainAndSignedNumbers) {
  EXPECT_DOUBLE_EQ(parse_finite_number("250", "--amplitude-v"), 250.0);
  EXPECT_DOUBLE_EQ(parse_finite_number(" +4.0e4 ", "--frequency-hz"), 40000.0);
  EXPECT_DOUBLE_EQ(parse_finite_number("-3", "--load"), -3.0);
}

TEST(ParseFiniteNumber, RejectsGarbageNanAndInfWithTheOptionName) {
  for (const char* bad : {"", "abc", "12x", "nan", "inf", "-inf", "1e999"}) {
    try {
      parse_finite_number(bad, "--amplitude-v");
      FAIL() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("--amplitude-v"), std::string::npos) << e.what();
    }
  }
}

TEST(ParseNumberList, SplitsOnCommas) {
  EXPECT_EQ(parse_number_list("100,250, 400", "--amplitude-v"), (std::vector<double>{100, 250, 400}));
  EXPECT_EQ(parse_number_list("7", "--amplitude-v"), (std::vector<double>{7}));
}

TEST(ParseNumberList, RejectsEmptyEntries) {
  EXPECT_THROW(parse_number_list("100,,400", "--amplitude-v"), std::invalid_argument);
  EXPECT_THROW(parse_number_list("100,", "--amplitude-v"), std::invalid_argument);
  EXPECT_THROW(parse_number_list("", "--amplitude-v"), std::invalid_argument);
}

TEST(ParseRange, ExpandsStartStopStepInclusive) {
  const auto values = parse_range_or_value("39000:40000:250", "--frequency-hz");
  EXPECT_EQ(values, (std::vector<double>{39000, 39250, 39500, 39750, 40000}));
}

TEST(ParseRange, IncludesStopDespiteRounding) {
  const auto values = parse_range_or_value("39.0:40.0:0.1", "--frequency-hz");
  ASSERT_EQ(values.size(), 11u);
  EXPECT_NEAR(values.back(), 40.0, 1e-9);
}

TEST(ParseRange, SingleValueIsOnePoint) {
  EXPECT_EQ(parse_range_or_value("40000", "--frequency-hz"), (std::vector<double>{40000}));
}

TEST(ParseRange, RejectsBadRanges) {
  EXPECT_THROW(parse_range_or_value("40000:39000:100", "--frequency-hz"), std::invalid_argument);
  EXPECT_THROW(parse_range_or_value("39000:40000:0", "--frequency-hz"), std::invalid_argument);
  EXPECT_THROW(parse_range_or_value("39000:40000:-5", "--frequency-hz"), std::invalid_argument);
  EXPECT_THROW(parse_range_or_value("39000:40000", "--frequency-hz"), std::invalid_argument);
  EXPECT_THROW(parse_range_or_value("1:2:3:4", "--frequency-hz"), std::invalid_argument);
  EXPECT_THROW(parse_range_or_value("0:1e9:1", "--frequency-hz"), std::invalid_argument);
}

}  // namespace
}  // namespace swum::host
