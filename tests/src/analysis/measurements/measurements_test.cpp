// Measurements CSV (docs/discrepancy.md): accepted layouts and errors naming line and column.
#include "analysis/measurements/measurements.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

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
      "# session 1\nload_n,amplitude_v,frequency_hz,speed_mm_s,tip_normal_um,time_s\n"
      "1.5,250,40300,310.5,,12\n\n0,100,40100,,1.2,15\n",
      "data.csv");
  ASSERT_EQ(set.rows.size(), 2u);
  EXPECT_TRUE(set.has_time);
  EXPECT_TRUE(set.has_quantity[0]);
  EXPECT_TRUE(set.has_quantity[1]);
  EXPECT_FALSE(set.has_quantity[2]);
  EXPECT_EQ(set.rows[0].amplitude_v, 250.0);
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
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n,speed_mm_s\n100,40000,0,abc\n"),
            "data.csv:2:4: column speed_mm_s: 'abc' is not a number");
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n,speed_mm_s\n100,40000,0\n"),
            "data.csv:2:4: expected 4 cells, found 3");
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,speed_mm_s\n"),
            "data.csv:1:4: missing column load_n (required: amplitude_v, frequency_hz, load_n)");
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n\n100,40000,0\n"),
            "data.csv:1:4: no measured quantity: add speed_mm_s, tip_normal_um or tip_tangential_um");
  EXPECT_NE(error_of("amplitude_v,frequency_hz,load_n,speed,x\n").find("data.csv:1:4: unknown column 'speed'"),
            std::string::npos);
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n,speed_mm_s\n-5,40000,0,1\n"),
            "data.csv:2:1: column amplitude_v: must be >= 0");
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n,speed_mm_s\n5,0,0,1\n"),
            "data.csv:2:2: column frequency_hz: 0 is outside 1000..200000 Hz");
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n,speed_mm_s\n5,4e10,0,1\n"),
            "data.csv:2:2: column frequency_hz: 4e+10 is outside 1000..200000 Hz");
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n,speed_mm_s\n1e308,40000,0,1\n"),
            "data.csv:2:1: column amplitude_v: 1e+308 is outside 0..10000 V");
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n,speed_mm_s\n5,40000,0,inf\n"),
            "data.csv:2:4: column speed_mm_s: 'inf' is not finite");
  std::string with_nul = "amplitude_v,frequency_hz,load_n,speed_mm_s\n5,4";
  with_nul += '\0';
  with_nul += "0000,0,1\n";  // a NUL must not cut the message short
  EXPECT_EQ(error_of(with_nul), "data.csv:2:2: column frequency_hz: '4\\x000000' is not a number");
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n,speed_mm_s\n5,40000,0,\n"),
            "data.csv:2: no measured value in this row");
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n,time_s,speed_mm_s\n5,40000,0,,3\n"),
            "data.csv:2:4: column time_s is empty");
  EXPECT_EQ(error_of("amplitude_v,amplitude_v,load_n\n"), "data.csv:1:2: column amplitude_v appears twice");
  EXPECT_EQ(error_of(""), "data.csv:1: no header line (the file is empty)");
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n,speed_mm_s\n"), "data.csv:2: no data rows");
}

// `swum sweep` on a device (host/output/sweep_table.cpp): time_s and sweep after load_n, the spread
// before status; failed points have empty measured cells.
constexpr const char* kDeviceSweep =
    "amplitude_v,frequency_hz,load_n,time_s,sweep,speed_mm_s,tip_normal_um,tip_tangential_um,speed_spread_mm_s,status\n"
    "250,40500,0,0.210,0,120.5,1.1,0.9,0.8,ok\n"
    "250,40400,0,0.310,0,140.2,1.2,1.0,0.7,unsettled\n"
    "250,40300,0,0.390,0,,,,,fault_numerical\n"
    "250,40200,0,0.560,1,150.1,1.3,1.1,0.9,ok\n"
    "250,40100,0,0.600,1,,,,,timeout\n"
    "250,40000,0,0.650,1,,,,,fault_7\n"
    "250,39900,0,0.700,2,,,,,no_drive\n";

TEST(Measurements, ReadsADeviceSweepLeavingOutAndCountingThePointsItDidNotMeasure) {
  const MeasurementSet set = parse_measurements_csv(kDeviceSweep, "sweep.csv");
  ASSERT_EQ(set.rows.size(), 3u);
  EXPECT_TRUE(set.has_time);
  EXPECT_TRUE(set.has_sweep);
  EXPECT_EQ(set.time_column, "time_s");
  EXPECT_EQ(set.rows[1].frequency_hz, 40400.0);  // unsettled: the values are still used
  EXPECT_EQ(*set.rows[2].sweep, 1);
  EXPECT_EQ(*set.rows[2].time_s, 0.56);
  EXPECT_EQ(set.rows[2].source_line, 5);
  EXPECT_EQ(set.ignored_columns, std::vector<std::string>{"speed_spread_mm_s"});
  EXPECT_EQ(set.skipped_rows, 4);
  EXPECT_EQ(set.skipped_by_reason.at("fault_numerical"), 1);
  EXPECT_EQ(set.skipped_by_reason.at("no_drive"), 1);
  EXPECT_EQ(measurement_note(set),
            "note: ignored column speed_spread_mm_s (informational); 4 rows left out (1 fault_7, "
            "1 fault_numerical, 1 no_drive, 1 timeout)");
  // The sweep ids survive the writer.
  const MeasurementSet again = parse_measurements_csv(format_measurements_csv(set), "again");
  ASSERT_EQ(again.rows.size(), 3u);
  EXPECT_TRUE(again.has_sweep);
  EXPECT_EQ(*again.rows[0].sweep, 0);
  EXPECT_EQ(*again.rows[2].sweep, 1);
  EXPECT_EQ(*again.rows[2].time_s, 0.56);
  EXPECT_EQ(measurement_note(again), "");
}

TEST(Measurements, ReadsAModelSweepWithoutTimeOrSweepIds) {
  const MeasurementSet set = parse_measurements_csv(
      "amplitude_v,frequency_hz,load_n,speed_mm_s,tip_normal_um,tip_tangential_um,status\n"
      "300,40400,0,210.5,1.4,1.2,ok\n300,40300,0,,,,diverged\n300,40200,0,250,1.5,1.3,ok\n",
      "model.csv");
  ASSERT_EQ(set.rows.size(), 2u);
  EXPECT_FALSE(set.has_time);
  EXPECT_FALSE(set.has_sweep);
  EXPECT_FALSE(set.rows[0].sweep.has_value());
  EXPECT_TRUE(set.ignored_columns.empty());
  EXPECT_EQ(measurement_note(set), "note: 1 row left out (1 diverged)");
}

// `swum log` (host/output/log_table.h): the device clock is the time; rows where the drive is off,
// in fault or at another phase are left out; each running stretch is one sweep.
TEST(Measurements, ReadsALogByTheDeviceClockAndItsRunningStretches) {
  const MeasurementSet set = parse_measurements_csv(
      "host_time_s,device_time_s,speed_mm_s,position_mm,tip_normal_um,tip_tangential_um,frequency_hz,amplitude_v,"
      "phase_deg,load_n,state,fault_code,last_reject,lateness_p99_us,lateness_max_us,overruns\n"
      "0.000100,12.000,0.000,0.000,0.000,0.000,40400.000,0.0,90.00,0.000,0,0,0,12,40,0\n"
      "0.010100,12.010,0.000,0.000,0.000,0.000,40400.000,0.0,90.00,0.000,1,0,0,12,40,0\n"
      "0.020100,12.020,150.000,1.500,1.200,1.000,40400.000,250.0,90.00,0.000,1,0,0,12,40,0\n"
      "0.030100,12.030,151.000,3.000,1.210,1.010,40400.000,250.0,90.00,0.000,1,0,0,12,40,0\n"
      "0.040100,12.040,0.000,3.000,0.000,0.000,40400.000,0.0,90.00,0.000,2,2,0,12,40,0\n"
      "0.050100,12.050,152.000,4.500,1.220,1.020,40300.000,250.0,90.00,1.000,1,0,0,12,40,0\n"
      "0.060100,12.060,-150.000,3.000,1.200,1.000,40300.000,250.0,-90.00,1.000,1,0,0,12,40,0\n"
      "0.070100,12.070,0.000,3.000,0.000,0.000,40300.000,0.0,90.00,1.000,2,1,0,12,40,0\n",
      "log.csv");
  ASSERT_EQ(set.rows.size(), 3u);
  EXPECT_EQ(set.time_column, "device_time_s");
  EXPECT_EQ(*set.rows[0].time_s, 12.02);
  EXPECT_EQ(*set.rows[0].value(Quantity::tip_tangential), 1.0);
  EXPECT_TRUE(set.has_sweep);
  EXPECT_TRUE(set.sweeps_from_state);
  EXPECT_EQ(*set.rows[0].sweep, 0);
  EXPECT_EQ(*set.rows[1].sweep, 0);
  EXPECT_EQ(*set.rows[2].sweep, 1);  // after the fault the drive started again from rest
  EXPECT_EQ(set.rows[2].load_n, 1.0);
  EXPECT_EQ(set.ignored_columns, (std::vector<std::string>{"host_time_s", "position_mm", "last_reject",
                                                           "lateness_p99_us", "lateness_max_us", "overruns"}));
  EXPECT_EQ(set.skipped_by_reason.at("drive_off"), 2);  // state 0, and state 1 at 0 V
  EXPECT_EQ(set.skipped_by_reason.at("fault_numerical"), 1);
  EXPECT_EQ(set.skipped_by_reason.at("fault_command_timeout"), 1);
  EXPECT_EQ(set.skipped_by_reason.at("phase_not_90_deg"), 1);
  EXPECT_EQ(measurement_note(set),
            "note: ignored columns host_time_s, position_mm, last_reject, lateness_p99_us, lateness_max_us, "
            "overruns (informational); time_s from device_time_s (the device clock); 5 rows left out "
            "(2 drive_off, 1 fault_command_timeout, 1 fault_numerical, 1 phase_not_90_deg)");
}

TEST(Measurements, SweepAndLogColumnsAreCheckedToo) {
  const std::string sweep_header = "amplitude_v,frequency_hz,load_n,time_s,sweep,speed_mm_s,status\n";
  EXPECT_EQ(error_of(sweep_header + "250,40500,0,0.2,0,120,okay\n"),
            "data.csv:2:7: column status: unknown status 'okay' (known: ok, unsettled, diverged, "
            "fault_numerical, fault_command_timeout, fault_<n>, timeout, no_drive)");
  EXPECT_EQ(error_of(sweep_header + "250,40500,0,0.2,0,120,fault_x\n").substr(0, 53),
            "data.csv:2:7: column status: unknown status 'fault_x'");
  EXPECT_EQ(error_of(sweep_header + "250,40500,0,0.2,0,120,\n"), "data.csv:2:7: column status is empty");
  EXPECT_EQ(error_of(sweep_header + "250,40500,0,0.2,-1,120,ok\n"), "data.csv:2:5: column sweep: must be >= 0");
  EXPECT_EQ(error_of(sweep_header + "250,40500,0,0.2,1.5,120,ok\n"),
            "data.csv:2:5: column sweep: 1.5 is not a whole number");
  EXPECT_EQ(error_of(sweep_header + "250,40500,0,0.2,,120,ok\n"), "data.csv:2:5: column sweep is empty");
  // A point left out still has its operating point checked (a typo is a typo).
  EXPECT_EQ(error_of(sweep_header + "250,4e10,0,0.2,0,,timeout\n"),
            "data.csv:2:2: column frequency_hz: 4e+10 is outside 1000..200000 Hz");
  EXPECT_EQ(error_of(sweep_header + "250,40500,0,0.2,0,,timeout\n250,40400,0,0.3,0,,timeout\n"),
            "data.csv:4: no usable rows: 2 rows left out (2 timeout)");
  EXPECT_EQ(error_of(sweep_header + "250,40500,0,0.2,0,,ok\n"), "data.csv:2: no measured value in this row");
  // Informational columns are known by their exact names: a near miss is a typo.
  EXPECT_NE(error_of("amplitude_v,frequency_hz,load_n,speed_mm_s,speed_spread\n")
                .find("data.csv:1:5: unknown column 'speed_spread' (known: amplitude_v,"),
            std::string::npos);
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n,speed_mm_s,overruns,overruns\n"),
            "data.csv:1:6: column overruns appears twice");
  EXPECT_EQ(error_of("amplitude_v,frequency_hz,load_n,time_s,device_time_s,speed_mm_s\n"),
            "data.csv:1:5: columns time_s and device_time_s both give the time: keep one");
  const std::string log_header =
      "device_time_s,amplitude_v,frequency_hz,load_n,speed_mm_s,phase_deg,state,fault_code\n";
  EXPECT_EQ(error_of(log_header + "1.0,250,40500,0,120,90,5,0\n"),
            "data.csv:2:7: column state: 5 is not a drive state (0 disabled, 1 running, 2 fault)");
  EXPECT_EQ(error_of(log_header + "1.0,250,40500,0,120,90,1.5,0\n"),
            "data.csv:2:7: column state: 1.5 is not a whole number");
  EXPECT_EQ(error_of(log_header + "1.0,250,40500,0,120,90,2,\n"), "data.csv:2:8: column fault_code is empty");
  EXPECT_EQ(error_of(log_header + "1.0,250,40500,0,120,,1,0\n"), "data.csv:2:6: column phase_deg is empty");
  // A log row before the device clock arrived is left out with its reason; the file is refused
  // only when no row is left.
  EXPECT_EQ(error_of(log_header + ",250,40500,0,120,90,1,0\n"),
            "data.csv:3: no usable rows: 1 row left out (1 no_device_time)");
  const MeasurementSet set = parse_measurements_csv(
      log_header + ",250,40500,0,120,90,1,0\n0.5,250,40500,0,121,90,1,0\n", "data.csv");
  ASSERT_EQ(set.rows.size(), 1u);
  EXPECT_EQ(set.skipped_by_reason.at("no_device_time"), 1);
  EXPECT_EQ(*set.rows[0].time_s, 0.5);
}

TEST(Measurements, OperatingPointsNeedNoQuantities) {
  const MeasurementSet points = parse_operating_points_csv("amplitude_v,frequency_hz,load_n,time_s\n200,40500,1,0\n",
                                                           "points.csv");
  ASSERT_EQ(points.rows.size(), 1u);
  EXPECT_TRUE(points.has_time);
}

}  // namespace
}  // namespace swum
