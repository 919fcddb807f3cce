// The files the host tool writes, read back: the sweep table in both layouts (model and
// device), and `swum sweep` / `swum log` output taken as measurements by the discrepancy
// workflow (src/analysis/measurements.h) — real formatter text from the fake device.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "analysis/measurements.h"
#include "device/device_sweep.h"
#include "fake_device.h"
#include "output/log_table.h"
#include "output/sweep_table.h"

namespace swum::host {
namespace {

using test::FakeDevice;

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

// A live sweep of two voltages with a numerical fault at 40200 Hz in the first.
std::vector<SweepRow> live_sweep_with_a_fault() {
  FakeDevice device;
  device.fault_at_frequency_hz = 40200.0;
  DeviceSweepPlan p;
  p.voltages = {200, 250};
  p.frequencies_hz = {40400, 40300, 40200, 40100};
  p.settle_s = 0.04;
  p.dwell_s = 0.02;
  p.ramp_vpp_per_s = 4000.0;
  p.poll_interval_s = 0.0;
  std::vector<SweepRow> rows;
  sweep_device(device, p, rows);
  return rows;
}

TEST(SweepTable, ADeviceSweepCarriesTimeAndSweepAndReadsBack) {
  const std::vector<SweepRow> rows = live_sweep_with_a_fault();
  const std::string csv = format_sweep_csv(rows);
  EXPECT_EQ(first_line(csv),
            "vpp,frequency_hz,load_n,time_s,sweep,speed_mm_s,tip_normal_um,tip_tangential_um,speed_spread_mm_s,status");
  const std::vector<SweepRow> again = parse_sweep_csv(csv, "sweep.csv");
  ASSERT_EQ(again.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(again[i].ok, rows[i].ok) << i;
    EXPECT_EQ(again[i].status, rows[i].status) << i;
    ASSERT_TRUE(again[i].time_s && again[i].sweep) << i;
    EXPECT_NEAR(*again[i].time_s, *rows[i].time_s, 0.0005) << "written to the ms";
    EXPECT_EQ(*again[i].sweep, *rows[i].sweep);
  }
}

TEST(SweepTable, AModelSweepKeepsTheOfflineLayout) {
  SweepRow ok{300, 40400, 0, true, "ok", 210.5, 1.4, 1.2};
  SweepRow diverged{300, 40300, 0, false, "diverged"};
  const std::string csv = format_sweep_csv({ok, diverged});
  EXPECT_EQ(csv, "vpp,frequency_hz,load_n,speed_mm_s,tip_normal_um,tip_tangential_um,status\n"
                 "300,40400,0,210.5,1.4,1.2,ok\n300,40300,0,,,,diverged\n");
  const std::vector<SweepRow> again = parse_sweep_csv(csv, "model.csv");
  ASSERT_EQ(again.size(), 2u);
  EXPECT_FALSE(again[0].time_s || again[0].sweep);
  EXPECT_FALSE(again[1].ok);
}

// The row-by-row writers produce format_sweep_csv's bytes.
TEST(SweepTable, HeaderAndRowsAreTheWholeTable) {
  SweepRow ok{300, 40400, 0, true, "ok", 210.5, 1.4, 1.2};
  SweepRow diverged{300, 40300, 0, false, "diverged"};
  EXPECT_EQ(sweep_layout_of({ok, diverged}), kModelSweep);
  EXPECT_EQ(format_sweep_header(kModelSweep) + format_sweep_row(kModelSweep, ok) +
                format_sweep_row(kModelSweep, diverged),
            format_sweep_csv({ok, diverged}));
  SweepRow measured = ok;
  measured.time_s = 1.25;
  measured.sweep = 3;
  measured.speed_spread_mm_s = 0.5;
  SweepRow timeout{300, 40300, 0, false, "timeout"};
  timeout.time_s = 2.5;
  timeout.sweep = 3;
  EXPECT_EQ(sweep_layout_of({measured, timeout}), kDeviceSweep);
  EXPECT_EQ(format_sweep_header(kDeviceSweep) + format_sweep_row(kDeviceSweep, measured) +
                format_sweep_row(kDeviceSweep, timeout),
            format_sweep_csv({measured, timeout}));
}

TEST(SweepTable, ABadTimeOrSweepCellNamesLineAndColumn) {
  const std::string header = "vpp,frequency_hz,load_n,time_s,sweep,speed_mm_s,status\n";
  auto error_of = [](const std::string& text) {
    try {
      (void)parse_sweep_csv(text, "s.csv");
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_of(header + "200,40400,0,0.5,1.5,100,ok\n"),
            "s.csv line 2 column sweep: 1.5 is not a sweep id (a whole number >= 0)");
  EXPECT_EQ(error_of(header + "200,40400,0,0.5,-1,100,ok\n"),
            "s.csv line 2 column sweep: -1 is not a sweep id (a whole number >= 0)");
  EXPECT_EQ(error_of(header + "200,40400,0,-0.5,0,100,ok\n"), "s.csv line 2 column time_s: must be >= 0");
  EXPECT_NE(error_of(header + "200,40400,0,x,0,100,ok\n").find("s.csv line 2 column time_s"), std::string::npos);
}

TEST(MeasurementFiles, ADeviceSweepIsAMeasurementFile) {
  const std::vector<SweepRow> rows = live_sweep_with_a_fault();
  const MeasurementSet set = parse_measurements_csv(format_sweep_csv(rows), "sweep.csv");
  ASSERT_EQ(set.rows.size(), rows.size() - 1);  // the faulted point is left out
  EXPECT_TRUE(set.has_time && set.has_sweep);
  for (std::size_t i = 0, k = 0; i < rows.size(); ++i) {
    if (!rows[i].ok) continue;
    const Measurement& m = set.rows[k++];
    EXPECT_EQ(m.frequency_hz, rows[i].frequency_hz);
    EXPECT_EQ(*m.sweep, *rows[i].sweep);
    EXPECT_NEAR(*m.time_s, *rows[i].time_s, 0.0005);
    EXPECT_NEAR(*m.value(Quantity::speed), rows[i].speed_mm_s, 1e-5 * std::abs(rows[i].speed_mm_s));  // 6 digits
  }
  EXPECT_EQ(measurement_note(set),
            "note: ignored column speed_spread_mm_s (informational); 1 row left out (1 fault_numerical)");
}

TEST(MeasurementFiles, ALogIsAMeasurementFile) {
  // The log of a fake device: off, running at 250 Vpp, a numerical fault, running again.
  FakeDevice device;
  device.watchdog_s = 0.0;
  std::string csv = kLogCsvHeader;
  auto log = [&](int samples) {
    for (int k = 0; k < samples; ++k) {
      csv += format_log_row(0.001 * device.reads, device.read());
    }
  };
  log(3);
  device.set_slew(0.0, 0.0);
  device.set_drive({40300, 250, 90, 0});
  device.command(DeviceAction::enable);
  log(4);
  device.fault_at_frequency_hz = 40200.0;
  device.set_drive({40200, 250, 90, 0});
  log(2);
  device.command(DeviceAction::reset_fault);
  device.command(DeviceAction::enable);
  device.set_drive({40100, 250, 90, 0});
  log(3);
  const MeasurementSet set = parse_measurements_csv(csv, "log.csv");
  ASSERT_EQ(set.rows.size(), 7u);
  EXPECT_EQ(set.time_column, "device_time_s");
  EXPECT_NEAR(*set.rows[0].time_s, 4 * device.read_step_s, 1e-9);
  for (std::size_t i = 0; i < set.rows.size(); ++i) EXPECT_EQ(*set.rows[i].sweep, i < 4 ? 0 : 1) << i;
  EXPECT_EQ(set.rows.back().frequency_hz, 40100.0);
  EXPECT_EQ(set.skipped_by_reason.at("drive_off"), 3);
  EXPECT_EQ(set.skipped_by_reason.at("fault_numerical"), 2);
  EXPECT_NE(measurement_note(set).find("5 rows left out (3 drive_off, 2 fault_numerical)"), std::string::npos);
}

}  // namespace
}  // namespace swum::host
