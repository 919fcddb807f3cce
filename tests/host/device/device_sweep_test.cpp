// The live sweep procedure (host/device/device_sweep.cpp) on a fake device with the emulator's
// contract: downward sweeps from zero amplitude, a fed watchdog, measured speeds, recovery from
// a fault, rejected commands and Ctrl-C never leave the drive on.
#include "device/device_sweep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <limits>

#include "../fake_device.h"
#include "commands/command_error.h"
#include "device/stop_signal.h"

namespace swum::host {
namespace {

using test::FakeDevice;

DeviceSweepPlan plan_for(std::vector<double> voltages, std::vector<double> frequencies) {
  DeviceSweepPlan p;
  p.voltages = std::move(voltages);
  p.frequencies_hz = std::move(frequencies);
  p.settle_s = 0.04;
  p.dwell_s = 0.02;
  p.amplitude_slew_v_per_s = 4000.0;
  p.poll_interval_s = 0.0;  // the fake answers instantly; its clock advances per read
  return p;
}

TEST(DeviceSweep, SweepsEachVoltageDownwardAndMeasuresTheSteadySpeed) {
  FakeDevice device;
  std::vector<SweepRow> rows;
  sweep_device(device, plan_for({100, 300}, {40000, 40600, 40200, 40400}), rows);
  ASSERT_EQ(rows.size(), 8u);
  for (std::size_t v = 0; v < 2; ++v) {
    for (std::size_t i = 1; i < 4; ++i) EXPECT_LT(rows[4 * v + i].frequency_hz, rows[4 * v + i - 1].frequency_hz);
  }
  for (const SweepRow& r : rows) {
    ASSERT_TRUE(r.ok) << r.status;
    // Settled for 40 ms = 8 time constants: within 0.1 % of the steady value.
    EXPECT_NEAR(r.speed_mm_s, FakeDevice::steady_speed_mm_s(r.frequency_hz, r.amplitude_v),
                1e-3 * FakeDevice::steady_speed_mm_s(r.frequency_hz, r.amplitude_v));
    EXPECT_GE(r.speed_spread_mm_s, 0.0);
  }
  EXPECT_EQ(device.state, 0) << "drive must be off at the end";
  EXPECT_EQ(device.actions.back(), DeviceAction::disable);
  EXPECT_EQ(device.slew_v_per_s, 4000.0);
  EXPECT_EQ(device.faults_tripped, 0);
}

TEST(DeviceSweep, EachVoltageStartsAtZeroAmplitudeAboveResonance) {
  FakeDevice device;
  std::vector<SweepRow> rows;
  sweep_device(device, plan_for({100, 300}, {40000, 40500}), rows);
  // The enable of each voltage comes with amplitude 0 at the highest frequency.
  EXPECT_EQ(std::count(device.actions.begin(), device.actions.end(), DeviceAction::enable), 2);
  bool saw_zero_at_top = false;
  for (const DriveSetpoint& s : device.setpoints) {
    if (s.amplitude_v == 0.0 && s.frequency_hz == 40500.0) saw_zero_at_top = true;
    if (s.amplitude_v > 0.0) {
      EXPECT_TRUE(saw_zero_at_top) << "voltage applied before a zero-amplitude start";
    }
  }
}

TEST(DeviceSweep, KeepsTheWatchdogFedDuringLongSettles) {
  FakeDevice device;
  device.watchdog_s = 0.1;
  DeviceSweepPlan p = plan_for({200}, {40300, 40200});
  p.settle_s = 0.5;  // 5 watchdog periods with nothing but reads
  std::vector<SweepRow> rows;
  sweep_device(device, p, rows);
  EXPECT_EQ(device.faults_tripped, 0);
  EXPECT_LE(device.longest_command_gap_s, p.keep_alive_s + 2 * device.read_step_s);
  for (const SweepRow& r : rows) EXPECT_TRUE(r.ok) << r.status;
}

TEST(DeviceSweep, AFaultMarksThePointAndTheSweepRecovers) {
  FakeDevice device;
  device.fault_at_frequency_hz = 40200.0;
  std::vector<SweepRow> rows;
  sweep_device(device, plan_for({200}, {40400, 40300, 40200, 40100}), rows);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_TRUE(rows[1].ok);
  EXPECT_FALSE(rows[2].ok);
  EXPECT_EQ(rows[2].status, "fault_numerical");
  EXPECT_TRUE(rows[3].ok) << rows[3].status;
  EXPECT_NEAR(rows[3].speed_mm_s, FakeDevice::steady_speed_mm_s(40100, 200), 0.5);
  EXPECT_NE(std::find(device.actions.begin(), device.actions.end(), DeviceAction::reset_fault), device.actions.end());
  EXPECT_EQ(device.state, 0);
}

// time_s: the device clock at the start of each dwell window, counted from the first read of the
// session; sweep: one id per (load, voltage) curve, in session order.
TEST(DeviceSweep, RecordsTheDeviceClockAndTheContinuousSweepOfEachPoint) {
  FakeDevice device;
  device.time_s = 1000.0;  // the device has been up for a while: the session still starts at 0
  DeviceSweepPlan p = plan_for({100, 300}, {40000, 40400, 40200});
  p.loads_n = {0.0, 1.0};
  std::vector<SweepRow> rows;
  sweep_device(device, p, rows);
  ASSERT_EQ(rows.size(), 12u);
  const double session_start_s = 1000.0 + device.read_step_s;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const SweepRow& r = rows[i];
    ASSERT_TRUE(r.ok) << r.status;
    ASSERT_TRUE(r.time_s && r.sweep);
    EXPECT_EQ(*r.sweep, static_cast<int>(i / 3)) << "one sweep per (load, voltage) curve";
    // The dwell began once the settle had passed on the device clock after the setpoint of
    // this point arrived (the last setpoint for it), within the fake's read step.
    std::size_t k = device.setpoints.size();
    while (k-- > 0) {
      const DriveSetpoint& s = device.setpoints[k];
      if (s.frequency_hz == r.frequency_hz && s.amplitude_v == r.amplitude_v && s.load_n == r.load_n) break;
    }
    ASSERT_LT(k, device.setpoints.size());
    const double after_setpoint_s = session_start_s + *r.time_s - device.setpoint_times_s[k];
    EXPECT_GE(after_setpoint_s, p.settle_s - 1e-9) << i;
    EXPECT_LE(after_setpoint_s, p.settle_s + 3 * device.read_step_s + 1e-9) << i;
    if (i > 0) {
      EXPECT_GE(*r.time_s - *rows[i - 1].time_s, p.settle_s + p.dwell_s - 1e-9) << i;
    }
  }
  EXPECT_LT(*rows.back().time_s, device.time_s - session_start_s);
}

TEST(DeviceSweep, ARestartAfterAFaultStartsANewSweep) {
  FakeDevice device;
  device.fault_at_frequency_hz = 40200.0;
  std::vector<SweepRow> rows;
  sweep_device(device, plan_for({200, 250}, {40400, 40300, 40200, 40100}), rows);
  ASSERT_EQ(rows.size(), 8u);
  std::vector<int> sweeps;
  for (const SweepRow& r : rows) sweeps.push_back(r.sweep.value_or(-1));
  // 200 V: two points, the fault (still the first curve), the restarted rest; then 250 V.
  EXPECT_EQ(sweeps, (std::vector<int>{0, 0, 0, 1, 2, 2, 2, 2}));
  EXPECT_EQ(rows[2].status, "fault_numerical");
  ASSERT_TRUE(rows[2].time_s && rows[3].time_s);
  EXPECT_GT(*rows[2].time_s, *rows[1].time_s);
  EXPECT_GT(*rows[3].time_s, *rows[2].time_s);
}

TEST(DeviceSweep, ARejectedSetpointIsAnErrorNamingTheReasonAndTheDriveGoesOff) {
  FakeDevice device;
  device.max_frequency_hz = 40500.0;
  std::vector<SweepRow> rows;
  try {
    sweep_device(device, plan_for({200}, {40600, 40400}), rows);
    FAIL() << "no error";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("frequency out of range"), std::string::npos) << e.what();
  }
  EXPECT_EQ(device.state, 0);
  EXPECT_EQ(device.actions.back(), DeviceAction::disable);
}

TEST(DeviceSweep, ALostLinkPropagatesWithWhatWasMeasured) {
  FakeDevice device;
  std::vector<SweepRow> rows;
  DeviceSweepPlan p = plan_for({200}, {40400, 40300, 40200, 40100, 40000});
  device.fail_after_reads = 100;
  EXPECT_THROW(sweep_device(device, p, rows), DeviceError);
  EXPECT_GE(rows.size(), 1u);
  EXPECT_LT(rows.size(), 5u);
}

TEST(DeviceSweep, CtrlCStopsWithTheDriveOffAndKeepsTheRows) {
  StopSignal stop;
  StopSignal::reset_for_tests();
  FakeDevice device;
  device.on_read = [](int reads) {
    if (reads == 150) std::raise(SIGINT);
  };
  std::vector<SweepRow> rows;
  try {
    sweep_device(device, plan_for({200}, {40400, 40300, 40200, 40100, 40000}), rows);
    FAIL() << "no interruption";
  } catch (const CommandError& e) {
    EXPECT_EQ(e.exit_code(), kExitInterrupted);
  }
  StopSignal::reset_for_tests();
  EXPECT_EQ(device.state, 0);
  EXPECT_EQ(device.actions.back(), DeviceAction::disable);
  EXPECT_GE(rows.size(), 1u);
  EXPECT_LT(rows.size(), 5u);
}

// `swum sweep --resume`: the plan's order, what an interrupted file keeps, and a run that
// starts after the curves it keeps.
TEST(DeviceSweep, PointsAreListedInSweepOrder) {
  DeviceSweepPlan p = plan_for({100, 300}, {40000, 40400, 40200});
  p.loads_n = {0.0, 1.0};
  const std::vector<SweepRow> points = device_sweep_points(p);
  FakeDevice device;
  std::vector<SweepRow> rows;
  sweep_device(device, p, rows);
  ASSERT_EQ(points.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(points[i].amplitude_v, rows[i].amplitude_v) << i;
    EXPECT_EQ(points[i].frequency_hz, rows[i].frequency_hz) << i;
    EXPECT_EQ(points[i].load_n, rows[i].load_n) << i;
  }
}

TEST(DeviceSweep, AResumeKeepsTheWholeCurvesOnly) {
  const DeviceSweepPlan p = plan_for({100, 200, 300}, {40000, 40400, 40200});
  FakeDevice device;
  std::vector<SweepRow> rows;
  sweep_device(device, p, rows);
  ASSERT_EQ(rows.size(), 9u);
  std::size_t kept = 99;
  // Killed during the second curve (two of its three points in the file): keep the first.
  DeviceSweepStart start = device_sweep_start(p, {rows.begin(), rows.begin() + 5}, kept);
  EXPECT_EQ(kept, 3u);
  EXPECT_EQ(start.curves_done, 1u);
  EXPECT_EQ(start.first_sweep_id, 1);
  EXPECT_EQ(start.time_offset_s, *rows[2].time_s);
  // Killed after a whole curve, and before any point.
  start = device_sweep_start(p, {rows.begin(), rows.begin() + 6}, kept);
  EXPECT_EQ(kept, 6u);
  EXPECT_EQ(start.curves_done, 2u);
  start = device_sweep_start(p, {}, kept);
  EXPECT_EQ(kept, 0u);
  EXPECT_EQ(start.curves_done, 0u);
  EXPECT_EQ(start.first_sweep_id, 0);
  EXPECT_EQ(start.time_offset_s, 0.0);
}

TEST(DeviceSweep, AResumedSweepStartsTheNextCurveFromItsTopFrequencyAtRest) {
  const DeviceSweepPlan p = plan_for({100, 200, 300}, {40000, 40400, 40200});
  FakeDevice device;
  std::vector<SweepRow> rows;
  DeviceSweepStart start;
  start.curves_done = 1;
  start.first_sweep_id = 4;  // the kept rows had a restart after a fault
  start.time_offset_s = 12.5;
  sweep_device(device, p, rows, {}, start);
  const std::vector<SweepRow> points = device_sweep_points(p);
  ASSERT_EQ(rows.size(), 6u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_TRUE(rows[i].ok) << rows[i].status;
    EXPECT_EQ(rows[i].amplitude_v, points[3 + i].amplitude_v) << i;
    EXPECT_EQ(rows[i].frequency_hz, points[3 + i].frequency_hz) << i;
    EXPECT_EQ(rows[i].sweep, 4 + static_cast<int>(i / 3)) << i;
    EXPECT_GT(*rows[i].time_s, 12.5) << i;
    if (i > 0) {
      EXPECT_GT(*rows[i].time_s, *rows[i - 1].time_s) << i;
    }
  }
  // 100 V is never driven; 200 V starts at zero amplitude at the top frequency.
  EXPECT_EQ(std::count(device.actions.begin(), device.actions.end(), DeviceAction::enable), 2);
  for (const DriveSetpoint& s : device.setpoints) EXPECT_NE(s.amplitude_v, 100.0);
  const auto first_driven = std::find_if(device.setpoints.begin(), device.setpoints.end(),
                                         [](const DriveSetpoint& s) { return s.amplitude_v > 0.0; });
  ASSERT_NE(first_driven, device.setpoints.begin());
  EXPECT_EQ(std::prev(first_driven)->amplitude_v, 0.0);
  EXPECT_EQ(std::prev(first_driven)->frequency_hz, 40400.0);
  EXPECT_EQ(device.state, 0);
}

TEST(DeviceSweep, RefusesAnEmptyOrSillyPlan) {
  FakeDevice device;
  std::vector<SweepRow> rows;
  EXPECT_THROW(sweep_device(device, plan_for({}, {40000}), rows), std::invalid_argument);
  DeviceSweepPlan p = plan_for({100}, {40000});
  p.dwell_s = 0.0;
  EXPECT_THROW(sweep_device(device, p, rows), std::invalid_argument);
  p = plan_for({100}, {40000});
  p.keep_alive_s = 0.2;  // longer than the 50 ms the protocol allows
  EXPECT_THROW(sweep_device(device, p, rows), std::invalid_argument);
  p = plan_for({100}, {40000});
  p.amplitude_slew_v_per_s = 0.4;  // would be sent as 0 = "unlimited": a voltage step
  EXPECT_THROW(sweep_device(device, p, rows), std::invalid_argument);
  p = plan_for({100}, {40000});
  p.settle_s = std::numeric_limits<double>::infinity();  // would wait forever
  EXPECT_THROW(sweep_device(device, p, rows), std::invalid_argument);
  EXPECT_TRUE(device.actions.empty()) << "a bad plan must not touch the device";
}

}  // namespace
}  // namespace swum::host
