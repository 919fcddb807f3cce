// `swum control`'s loop (host/control/) on the fake device (its amplitude PI is
// tests/src/controllers/speed_pi_test.cpp's): lockstep stepping, the fault reaction (recoverable -> reset + re-enable
// after the hold-off, not recoverable -> drive off and stop, the retry limit) and the CSV row format.
#include "control/speed_control.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "../fake_device.h"

namespace swum::host {
namespace {

using test::FakeDevice;

SpeedControlSettings settings_for(double target_mm_s, double duration_s) {
  SpeedControlSettings s;
  s.target_mm_s = target_mm_s;
  s.frequency_hz = 40300.0;
  s.duration_s = duration_s;
  s.cycle_s = 0.001;
  s.gains = {0.5, 50.0, 500.0};
  return s;
}

struct ControlRun {
  std::vector<SpeedControlRow> rows;
  std::vector<std::string> events;
  SpeedControlResult result;
};

ControlRun run(FakeDevice& device, const SpeedControlSettings& s) {
  ControlRun r;
  SpeedControlHooks hooks;
  hooks.on_row = [&r](const SpeedControlRow& row) { r.rows.push_back(row); };
  hooks.on_event = [&r](const std::string& line) { r.events.push_back(line); };
  r.result = run_speed_control(device, s, hooks);
  return r;
}

FakeDevice lockstep_device() {
  FakeDevice d;
  d.lockstep_mode = true;
  d.read_step_s = 0.0;  // like swum-emu in lockstep: time moves only when stepped
  return d;
}

TEST(SpeedControl, LockstepReachesTheTargetAndSwitchesTheDriveOffAtTheEnd) {
  for (const double target : {300.0, -200.0}) {
    FakeDevice device = lockstep_device();
    const ControlRun r = run(device, settings_for(target, 0.3));
    ASSERT_EQ(r.rows.size(), 300u);
    EXPECT_TRUE(r.result.stop_reason.empty());
    EXPECT_LT(r.result.mean_abs_error_last_half_mm_s, 1.0) << target;
    EXPECT_NEAR(r.rows.back().speed_mm_s, target, 1.0);
    EXPECT_EQ(r.rows.front().action, DeviceAction::enable);
    EXPECT_EQ(r.rows[1].action, DeviceAction::keep_alive);
    EXPECT_EQ(*r.rows.back().tick, 3000u);  // 10 ticks per 1 ms cycle at 10 kHz
    EXPECT_EQ(device.steps, 301);           // + the drive-off step
    EXPECT_EQ(device.actions.back(), DeviceAction::disable);
    EXPECT_EQ(device.state, 0);
    EXPECT_EQ(device.faults_tripped, 0);  // every cycle fed the watchdog
  }
}

TEST(SpeedControl, RecoverableFaultIsResetAndReenabledAfterTheHoldoff) {
  FakeDevice device = lockstep_device();
  device.fault_schedule = {{0.1, 1}};
  SpeedControlSettings s = settings_for(300.0, 0.3);
  s.holdoff_cycles = 5;
  const ControlRun r = run(device, s);
  ASSERT_EQ(r.rows.size(), 300u);
  EXPECT_EQ(r.result.faults_seen, 1);
  EXPECT_EQ(r.result.retries, 1);
  EXPECT_TRUE(r.result.stop_reason.empty());
  ASSERT_EQ(r.events.size(), 1u);
  EXPECT_NE(r.events[0].find("command timeout (code 1): drive off; reset and re-enable after 5 cycles (retry 1 of 3)"),
            std::string::npos)
      << r.events[0];
  const auto faulted = std::find_if(r.rows.begin(), r.rows.end(), [](const auto& row) { return row.state == 2; });
  ASSERT_NE(faulted, r.rows.end());
  const std::size_t f = faulted - r.rows.begin();
  EXPECT_EQ(r.rows[f + 1].action, DeviceAction::disable);
  for (std::size_t i = f + 1; i <= f + 6; ++i) EXPECT_EQ(r.rows[i].amplitude_v_command, 0.0) << i;
  for (std::size_t i = f + 2; i <= f + 6; ++i) EXPECT_EQ(r.rows[i].action, DeviceAction::keep_alive) << i;
  EXPECT_EQ(r.rows[f + 7].action, DeviceAction::reset_fault);
  EXPECT_EQ(r.rows[f + 8].action, DeviceAction::enable);
  EXPECT_NEAR(r.rows.back().speed_mm_s, 300.0, 1.0);  // back at the target
}

TEST(SpeedControl, NonRecoverableFaultSwitchesTheDriveOffAndStops) {
  for (const int code : {2, 3, 4}) {
    FakeDevice device = lockstep_device();
    device.fault_schedule = {{0.05, code}};
    const ControlRun r = run(device, settings_for(300.0, 0.3));
    EXPECT_NE(r.result.stop_reason.find("code " + std::to_string(code) + ") at cycle"), std::string::npos);
    EXPECT_NE(r.result.stop_reason.find("not recoverable"), std::string::npos);
    EXPECT_EQ(r.result.retries, 0);
    ASSERT_LT(r.rows.size(), 300u);
    EXPECT_EQ(r.rows.back().action, DeviceAction::disable);
    EXPECT_EQ(r.rows.back().amplitude_v_command, 0.0);
    EXPECT_EQ(std::count(device.actions.begin(), device.actions.end(), DeviceAction::reset_fault), 0);
    EXPECT_NE(device.state, 1);
  }
}

TEST(SpeedControl, RecoverableFaultsStopTheRunWhenTheRetriesAreUsedUp) {
  FakeDevice device = lockstep_device();
  device.fault_schedule = {{0.05, 1}, {0.1, 1}, {0.15, 1}, {0.2, 1}};
  SpeedControlSettings s = settings_for(300.0, 0.3);
  s.max_retries = 2;
  const ControlRun r = run(device, s);
  EXPECT_EQ(r.result.retries, 2);
  EXPECT_EQ(r.result.faults_seen, 3);
  EXPECT_NE(r.result.stop_reason.find("--max-retries 2 used up"), std::string::npos) << r.result.stop_reason;
  EXPECT_EQ(r.rows.back().action, DeviceAction::disable);
  // An empty --recover set makes the command timeout final too.
  FakeDevice strict = lockstep_device();
  strict.fault_schedule = {{0.05, 1}};
  s.recoverable_faults.clear();
  EXPECT_NE(run(strict, s).result.stop_reason.find("not recoverable"), std::string::npos);
}

TEST(SpeedControl, RefusesATickRateTheDeviceDoesNotRun) {
  FakeDevice device = lockstep_device();
  device.tick_hz = 20000.0;
  try {
    run(device, settings_for(300.0, 0.1));
    FAIL() << "no error";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("--tick-hz 10000.000000 does not match the device"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(device.actions.back(), DeviceAction::disable);  // drive off before reporting
  SpeedControlSettings odd = settings_for(300.0, 0.1);
  odd.cycle_s = 0.00015;  // 1.5 ticks
  EXPECT_THROW(run(device, odd), std::invalid_argument);
}

TEST(SpeedControl, WallTimeDeviceRunsTheSameLawWithoutStepping) {
  FakeDevice device;  // not lockstep: set-point + read per cycle on the host clock
  const ControlRun r = run(device, settings_for(300.0, 0.05));
  EXPECT_EQ(r.rows.size(), 50u);
  EXPECT_EQ(device.steps, 0);
  EXPECT_FALSE(r.rows.front().tick.has_value());
  EXPECT_EQ(device.actions.front(), DeviceAction::enable);
  EXPECT_EQ(device.actions.back(), DeviceAction::disable);
  EXPECT_THROW(device.step(DriveSetpoint{}, DriveSlew{}, DeviceAction::keep_alive, 10), DeviceError);
}

TEST(SpeedControl, RowsHaveFixedPrecision) {
  SpeedControlRow row{12, 130, 0.013, 300.0, 299.9876543, 151.25, 40000.0, 1, 0, DeviceAction::keep_alive};
  EXPECT_EQ(format_speed_control_row(row),
            "12,130,0.013000,300.000000,299.987654,151.250000,40000.000000,1,0,keep_alive\n");
  row.tick.reset();
  row.action = DeviceAction::reset_fault;
  EXPECT_EQ(format_speed_control_row(row),
            "12,,0.013000,300.000000,299.987654,151.250000,40000.000000,1,0,reset_fault\n");
  // A target of 1e300 mm/s (only checked finite) is 308 characters through %.6f: the row keeps
  // every cell and its newline.
  row.target_mm_s = 1e300;
  const std::string huge = format_speed_control_row(row);
  EXPECT_GT(huge.size(), 320u);
  const std::string tail = ",151.250000,40000.000000,1,0,reset_fault\n";
  ASSERT_GT(huge.size(), tail.size());
  EXPECT_EQ(huge.substr(huge.size() - tail.size()), tail);
  EXPECT_EQ(std::count(huge.begin(), huge.end(), ','), 9);
}

}  // namespace
}  // namespace swum::host
