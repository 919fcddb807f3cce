#include "output/amplitude_csv.h"

#include <gtest/gtest.h>

#include <string>

#include "commands/command_error.h"

namespace swum::host {
namespace {

const char* kHeader = "amplitude_v,frequency_hz,tip_normal_um,tip_tangential_um\n";

std::string error_of(const std::string& text, int min_amplitudes = 4) {
  try {
    (void)parse_amplitude_csv(text, "data.csv", min_amplitudes);
  } catch (const CommandError& e) {
    return e.what();
  }
  return "";
}

TEST(AmplitudeCsv, ReadsRowsWithEmptyAmplitudeCells) {
  const auto rows = parse_amplitude_csv(std::string(kHeader) + "# comment\n50,39500,0.41,0.72\n\n100,39500,,1.28\n"
                                                               "150,39500,1.2,\r\n",
                                        "data.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_DOUBLE_EQ(rows[0].amplitude_v, 50.0);
  EXPECT_DOUBLE_EQ(*rows[0].tip_tangential_um, 0.72);
  EXPECT_FALSE(rows[1].tip_normal_um.has_value());
  EXPECT_DOUBLE_EQ(*rows[1].tip_tangential_um, 1.28);
  EXPECT_FALSE(rows[2].tip_tangential_um.has_value());
  EXPECT_EQ(rows[1].source_line, 5);
}

TEST(AmplitudeCsv, ColumnsInAnyOrderAndExtraColumnsIgnored) {
  const auto rows = parse_amplitude_csv(
      "branch,tip_tangential_um,amplitude_v,frequency_hz,tip_normal_um\n0,1,2,39000,3\n1,4,5,39000,6\n", "data.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_DOUBLE_EQ(rows[1].amplitude_v, 5.0);
  EXPECT_DOUBLE_EQ(*rows[1].tip_normal_um, 6.0);
  EXPECT_DOUBLE_EQ(*rows[1].tip_tangential_um, 4.0);
}

TEST(AmplitudeCsv, MissingColumnNamesFileLineAndColumn) {
  const std::string e = error_of("amplitude_v,frequency_hz,tip_normal_um\n1,2,3\n");
  EXPECT_NE(e.find("data.csv:1:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("missing column tip_tangential_um"), std::string::npos) << e;
}

TEST(AmplitudeCsv, NonNumericCellNamesFileLineAndColumn) {
  const std::string e = error_of(std::string(kHeader) + "50,39500,0.4,0.7\n100,39k5,0.8,1.3\n");
  EXPECT_NE(e.find("data.csv:3:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("frequency_hz"), std::string::npos) << e;
  EXPECT_NE(e.find("'39k5' is not a number"), std::string::npos) << e;
}

TEST(AmplitudeCsv, NegativeVoltageIsAnError) {
  const std::string e = error_of(std::string(kHeader) + "-50,39500,0.4,0.7\n");
  EXPECT_NE(e.find("data.csv:2:1:"), std::string::npos) << e;
  EXPECT_NE(e.find("negative"), std::string::npos) << e;
}

TEST(AmplitudeCsv, NegativeAmplitudeAndBadFrequencyAreErrors) {
  EXPECT_NE(error_of(std::string(kHeader) + "50,39500,-0.4,0.7\n").find("data.csv:2:3:"), std::string::npos);
  EXPECT_NE(error_of(std::string(kHeader) + "50,0,0.4,0.7\n").find("data.csv:2:2:"), std::string::npos);
  EXPECT_NE(error_of(std::string(kHeader) + "50,39500,inf,0.7\n").find("not finite"), std::string::npos);
}

TEST(AmplitudeCsv, WrongCellCountAndEmptyRowAreErrors) {
  EXPECT_NE(error_of(std::string(kHeader) + "50,39500,0.4\n").find("data.csv:2:"), std::string::npos);
  EXPECT_NE(error_of(std::string(kHeader) + "50,39500,,\n").find("both"), std::string::npos);
}

TEST(AmplitudeCsv, FewerAmplitudesThanParametersIsAnError) {
  const std::string e = error_of(std::string(kHeader) + "50,39500,0.4,\n100,39500,,1.3\n150,39500,1.2,\n");
  EXPECT_NE(e.find("data.csv:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("only 3 amplitude values"), std::string::npos) << e;
  EXPECT_NE(error_of("").find("data.csv:1:"), std::string::npos);
}

TEST(AmplitudeCsv, FormatRoundTrips) {
  std::vector<AmplitudeMeasurement> data(2);
  data[0] = {50.0, 39500.0, 0.41, std::nullopt, 0};
  data[1] = {100.0, 39250.0, std::nullopt, 1.25, 0};
  const auto back = parse_amplitude_csv(format_amplitude_csv(data), "x.csv", 2);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_DOUBLE_EQ(*back[0].tip_normal_um, 0.41);
  EXPECT_FALSE(back[0].tip_tangential_um);
  EXPECT_DOUBLE_EQ(*back[1].tip_tangential_um, 1.25);
}

}  // namespace
}  // namespace swum::host
