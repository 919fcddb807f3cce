// Measurements CSV (docs/discrepancy.md): accepted layouts and errors naming line and column.
#include "analysis/measurements.h"

#include <gtest/gtest.h>

#include <string>

namespace swum {
namespace {

std::string error_of(const std::string& text) {
  try {
    (void)parse_measurements_csv(text, "data.csv");
  } catch (const MeasurementError& e) {
    return e.what();
  }
  return "";
}

TEST(Measurements, ParsesAnyColumnOrderCommentsAndEmptyCells) {
  const MeasurementSet set = parse_measurements_csv(
      "# session 1\nload_n,vpp,frequency_hz,speed_mm_s,tip_normal_um,time_s\n"
      "1.5,250,40300,310.5,,12\n\n0,100,40100,,1.2,15\n",
      "data.csv");
  ASSERT_EQ(set.rows.size(), 2u);
  EXPECT_TRUE(set.has_time);
  EXPECT_TRUE(set.has_quantity[0]);
  EXPECT_TRUE(set.has_quantity[1]);
  EXPECT_FALSE(set.has_quantity[2]);
  EXPECT_EQ(set.rows[0].vpp, 250.0);
  EXPECT_EQ(set.rows[0].load_n, 1.5);
  EXPECT_EQ(*set.rows[0].value(Quantity::speed), 310.5);
  EXPECT_FALSE(set.rows[0].value(Quantity::tip_normal).has_value());
  EXPECT_EQ(*set.rows[1].time_s, 15.0);
  EXPECT_EQ(set.rows[1].source_line, 5);  // comment, header, row, blank line, row
  // Round trip through the writer.
  const MeasurementSet again = parse_measurements_csv(format_measurements_csv(set), "again");
  ASSERT_EQ(again.rows.size(), 2u);
  EXPECT_EQ(*again.rows[1].value(Quantity::tip_normal), 1.2);
}

TEST(Measurements, ErrorsNameFileLineAndColumn) {
  EXPECT_EQ(error_of("vpp,frequency_hz,load_n,speed_mm_s\n100,40000,0,abc\n"),
            "data.csv:2:4: column speed_mm_s: 'abc' is not a number");
  EXPECT_EQ(error_of("vpp,frequency_hz,load_n,speed_mm_s\n100,40000,0\n"),
            "data.csv:2:4: expected 4 cells, found 3");
  EXPECT_EQ(error_of("vpp,frequency_hz,speed_mm_s\n"),
            "data.csv:1:4: missing column load_n (required: vpp, frequency_hz, load_n)");
  EXPECT_EQ(error_of("vpp,frequency_hz,load_n\n100,40000,0\n"),
            "data.csv:1:4: no measured quantity: add speed_mm_s, tip_normal_um or tip_tangential_um");
  EXPECT_NE(error_of("vpp,frequency_hz,load_n,speed,x\n").find("data.csv:1:4: unknown column 'speed'"),
            std::string::npos);
  EXPECT_EQ(error_of("vpp,frequency_hz,load_n,speed_mm_s\n-5,40000,0,1\n"),
            "data.csv:2:1: column vpp: must be >= 0");
  EXPECT_EQ(error_of("vpp,frequency_hz,load_n,speed_mm_s\n5,0,0,1\n"),
            "data.csv:2:2: column frequency_hz: 0 is outside 1000..200000 Hz");
  EXPECT_EQ(error_of("vpp,frequency_hz,load_n,speed_mm_s\n5,4e10,0,1\n"),
            "data.csv:2:2: column frequency_hz: 4e+10 is outside 1000..200000 Hz");
  EXPECT_EQ(error_of("vpp,frequency_hz,load_n,speed_mm_s\n1e308,40000,0,1\n"),
            "data.csv:2:1: column vpp: 1e+308 is outside 0..10000 Vpp");
  EXPECT_EQ(error_of("vpp,frequency_hz,load_n,speed_mm_s\n5,40000,0,inf\n"),
            "data.csv:2:4: column speed_mm_s: 'inf' is not finite");
  std::string with_nul = "vpp,frequency_hz,load_n,speed_mm_s\n5,4";
  with_nul += '\0';
  with_nul += "0000,0,1\n";  // a NUL must not cut the message short
  EXPECT_EQ(error_of(with_nul), "data.csv:2:2: column frequency_hz: '4\\x000000' is not a number");
  EXPECT_EQ(error_of("vpp,frequency_hz,load_n,speed_mm_s\n5,40000,0,\n"),
            "data.csv:2: no measured value in this row");
  EXPECT_EQ(error_of("vpp,frequency_hz,load_n,time_s,speed_mm_s\n5,40000,0,,3\n"),
            "data.csv:2:4: column time_s is empty");
  EXPECT_EQ(error_of("vpp,vpp,load_n\n"), "data.csv:1:2: column vpp appears twice");
  EXPECT_EQ(error_of(""), "data.csv:1: no header line (the file is empty)");
  EXPECT_EQ(error_of("vpp,frequency_hz,load_n,speed_mm_s\n"), "data.csv:2: no data rows");
}

TEST(Measurements, OperatingPointsNeedNoQuantities) {
  const MeasurementSet points =
      parse_operating_points_csv("vpp,frequency_hz,load_n,time_s\n200,40500,1,0\n", "points.csv");
  ASSERT_EQ(points.rows.size(), 1u);
  EXPECT_TRUE(points.has_time);
}

}  // namespace
}  // namespace swum
