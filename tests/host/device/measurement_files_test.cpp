// The files the host tool writes, read back: the sweep table in both layouts (model and
// device), and `swum sweep` / `swum log` output taken as measurements by the discrepancy
// workflow (src/analysis/measurements/measurements.h) — real formatter text from the fake device.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "../fake_device.h"
#include "analysis/measurements/measurements.h"
#include "device/device_sweep.h"
#include "output/log_table.h"
#include "output/sweep_table.h"

namespace swum::host {
namespace {

using test::FakeDevice;

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

// A live sweep of the fake device, short settle and dwell.
std::vector<SweepRow> live_sweep(FakeDevice& device, std::vector<double> voltages, std::vector<double> frequencies_hz) {
  DeviceSweepPlan p;
  p.voltages = std::move(voltages);
  p.frequencies_hz = std::move(frequencies_hz);
  p.settle_s = 0.04;
  p.dwell_s = 0.02;
  p.amplitude_slew_v_per_s = 4000.0;
  p.poll_interval_s = 0.0;
  std::vector<SweepRow> rows;
  sweep_device(device, p, rows);
  return rows;
}

// A live sweep of two voltages with a numerical fault at 40200 Hz in the first.
std::vector<SweepRow> live_sweep_with_a_fault() {
  FakeDevice device;
  device.fault_at_frequency_hz = 40200.0;
  return live_sweep(device, {200, 250}, {40400, 40300, 40200, 40100});
}

TEST(SweepTable, ADeviceSweepCarriesTimeAndSweepAndReadsBack) {
  const std::vector<SweepRow> rows = live_sweep_with_a_fault();
  const std::string csv = format_sweep_csv(rows);
  EXPECT_EQ(first_line(csv),
            "amplitude_v,frequency_hz,load_n,time_s,sweep,speed_mm_s,tip_normal_um,tip_tangential_um,speed_spread_mm_s,"
            "status,"
            "current_a_a,current_b_a,phase_a_deg,phase_b_deg,motional_phase_a_deg,motional_phase_b_deg,power_w,"
            "stator_temperature_c");
  const std::vector<SweepRow> again = parse_sweep_csv(csv, "sweep.csv");
  ASSERT_EQ(again.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(again[i].ok, rows[i].ok) << i;
    // Measured points carry the electrical means (6 digits), failed ones empty cells.
    EXPECT_EQ(again[i].electrical.has_value(), rows[i].ok) << i;
    EXPECT_EQ(again[i].stator_temperature_c.has_value(), rows[i].ok) << i;
    if (rows[i].ok) {
      EXPECT_NEAR(again[i].electrical->current_a_a, rows[i].electrical->current_a_a, 1e-6) << i;
      EXPECT_NEAR(again[i].electrical->power_w, rows[i].electrical->power_w, 1e-4) << i;
      EXPECT_NEAR(*again[i].stator_temperature_c, *rows[i].stator_temperature_c, 1e-4) << i;
    }
    EXPECT_EQ(again[i].status, rows[i].status) << i;
    ASSERT_TRUE(again[i].time_s && again[i].sweep) << i;
    EXPECT_NEAR(*again[i].time_s, *rows[i].time_s, 0.0005) << "written to the ms";
    EXPECT_EQ(*again[i].sweep, *rows[i].sweep);
  }
}

// A sweep's electrical cells are the means over the dwell; a device that does not report them
// (a board without the electrical registers or frames) leaves them empty.
TEST(SweepTable, ElectricalMeansOverTheDwellOrEmptyCells) {
  const std::vector<SweepRow> rows = live_sweep_with_a_fault();
  const SweepRow& first = rows.front();
  ASSERT_TRUE(first.ok && first.electrical && first.stator_temperature_c);
  EXPECT_NEAR(first.electrical->current_a_a, 6e-4 * 200, 1e-9);  // the fake: 0.6 mA per V
  EXPECT_NEAR(first.electrical->current_b_a, 0.98 * 6e-4 * 200, 1e-9);
  EXPECT_NEAR(first.electrical->phase_a_deg, 60.0, 1e-9);
  EXPECT_NEAR(first.electrical->power_w, 0.039 * 200, 1e-9);  // both phases
  EXPECT_GT(*first.stator_temperature_c, 20.0);

  FakeDevice device;
  device.electrical_port = false;
  const std::vector<SweepRow> plain = live_sweep(device, {200}, {40400});
  ASSERT_EQ(plain.size(), 1u);
  ASSERT_TRUE(plain[0].ok);
  EXPECT_FALSE(plain[0].electrical || plain[0].stator_temperature_c);
  const std::string line = format_sweep_row(kDeviceSweep, plain[0]);
  EXPECT_EQ(line.substr(line.size() - 12), ",ok,,,,,,,,\n");  // status, then eight empty cells
}

TEST(LogTable, ElectricalCellsToTheWiresResolutionOrEmpty) {
  DeviceTelemetry t;
  t.electrical = protocol::ElectricalValues{0.18346, 0.1791, 61.234, 58.7, -4.321, 3.2, 8.76, 8.1};
  t.stator_temperature_c = 20.004;
  const std::string row = format_log_row(0.5, t);
  EXPECT_NE(row.find(",0.1835,0.1791,61.23,58.70,-4.32,3.20,16.86,20.00\n"), std::string::npos) << row;
  EXPECT_EQ(std::count(row.begin(), row.end(), ','),
            std::count(kLogCsvHeader, kLogCsvHeader + std::strlen(kLogCsvHeader), ','));
  const std::string plain = format_log_row(0.5, DeviceTelemetry{});
  EXPECT_EQ(plain.substr(plain.size() - 9), ",,,,,,,,\n");
}

TEST(SweepTable, AModelSweepKeepsTheOfflineLayout) {
  SweepRow ok{300, 40400, 0, true, "ok", 210.5, 1.4, 1.2};
  SweepRow diverged{300, 40300, 0, false, "diverged"};
  const std::string csv = format_sweep_csv({ok, diverged});
  EXPECT_EQ(csv, "amplitude_v,frequency_hz,load_n,speed_mm_s,tip_normal_um,tip_tangential_um,status\n"
                 "300,40400,0,210.5,1.4,1.2,ok\n300,40300,0,,,,diverged\n");
  const std::vector<SweepRow> again = parse_sweep_csv(csv, "model.csv");
  ASSERT_EQ(again.size(), 2u);
  EXPECT_FALSE(again[0].time_s || again[0].sweep);
  EXPECT_FALSE(again[1].ok);
}

// A model sweep's electrical and sizing figures (issue 36) come back as written; a failed point
// has empty cells there too.
TEST(SweepTable, AModelSweepsElectricalFiguresRoundTrip) {
  SweepRow ok{300, 40060, 1, true, "ok", 150.5, 1.4, 1.2};
  ok.electrical = SweepElectrical{0.74, 0.74, 82.1, 82.0, -12.9, -10.1, 24.4};
  ok.sizing = SweepSizing{0.52, 0.51, 0.76, 0.75, 300, 299.5, 15.3, 9.1, 110.9, 110.7, 0.138, 0.082};
  SweepRow diverged{300, 40300, 0, false, "diverged"};
  const std::string csv = format_sweep_csv({ok, diverged});
  EXPECT_NE(csv.find(",current_rms_a_a,current_rms_b_a,current_peak_a_a,current_peak_b_a,voltage_a_v,voltage_b_v,"
                     "power_a_w,power_b_w,apparent_power_a_va,apparent_power_b_va,power_factor_a,power_factor_b\n"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find(",diverged" + std::string(8 + 12, ',') + "\n"), std::string::npos) << csv;  // 8 + 12 empty
  const std::vector<SweepRow> again = parse_sweep_csv(csv, "model.csv");
  ASSERT_EQ(again.size(), 2u);
  ASSERT_TRUE(again[0].sizing);
  EXPECT_EQ(*again[0].sizing, *ok.sizing);
  EXPECT_EQ(*again[0].electrical, *ok.electrical);
  EXPECT_FALSE(again[1].sizing);
}

// The row-by-row writers produce format_sweep_csv's bytes.
TEST(SweepTable, HeaderAndRowsAreTheWholeTable) {
  SweepRow ok{300, 40400, 0, true, "ok", 210.5, 1.4, 1.2};
  ok.electrical = SweepElectrical{0.74, 0.74, 82.1, 82.0, -12.9, -10.1, 24.4};
  ok.sizing = SweepSizing{0.52, 0.52, 0.76, 0.76, 300, 300, 15.3, 9.1, 110.9, 110.7, 0.138, 0.082};
  SweepRow diverged{300, 40300, 0, false, "diverged"};
  EXPECT_EQ(sweep_layout_of({ok, diverged}), kModelSweep);
  EXPECT_EQ(format_sweep_header(kModelSweep) + format_sweep_row(kModelSweep, ok) +
                format_sweep_row(kModelSweep, diverged),
            format_sweep_csv({ok, diverged}));
  SweepRow measured = ok;
  measured.sizing = std::nullopt;
  measured.time_s = 1.25;
  measured.sweep = 3;
  measured.speed_spread_mm_s = 0.5;
  measured.electrical = SweepElectrical{0.18, 0.17, 61.2, 58.8, -4.3, 3.2, 16.9};
  measured.stator_temperature_c = 20.5;
  SweepRow timeout{300, 40300, 0, false, "timeout"};
  timeout.time_s = 2.5;
  timeout.sweep = 3;
  EXPECT_EQ(sweep_layout_of({measured, timeout}), kDeviceSweep);
  EXPECT_EQ(format_sweep_header(kDeviceSweep) + format_sweep_row(kDeviceSweep, measured) +
                format_sweep_row(kDeviceSweep, timeout),
            format_sweep_csv({measured, timeout}));
  EXPECT_EQ(format_sweep_row(kDeviceSweep, measured),
            "300,40400,0,1.250,3,210.5,1.4,1.2,0.5,ok,0.18,0.17,61.2,58.8,-4.3,3.2,16.9,20.5\n");
  EXPECT_EQ(format_sweep_row(kDeviceSweep, timeout), "300,40300,0,2.500,3,,,,,timeout,,,,,,,,\n");
}

TEST(SweepTable, ABadTimeOrSweepCellNamesLineAndColumn) {
  const std::string header = "amplitude_v,frequency_hz,load_n,time_s,sweep,speed_mm_s,status\n";
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
            "note: ignored columns speed_spread_mm_s, current_a_a, current_b_a, phase_a_deg, phase_b_deg, "
            "motional_phase_a_deg, motional_phase_b_deg, power_w, stator_temperature_c (informational); 1 row left out "
            "(1 fault_numerical)");
}

TEST(MeasurementFiles, ALogIsAMeasurementFile) {
  // The log of a fake device: off, running at 250 V, a numerical fault, running again.
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
  // The log's electrical columns are informational: read past with a note, never an error.
  EXPECT_NE(measurement_note(set).find("motional_phase_a_deg, motional_phase_b_deg, power_w, stator_temperature_c"),
            std::string::npos)
      << measurement_note(set);
}

}  // namespace
}  // namespace swum::host
