// `swum track`'s loop (host/track/track_run.h) on the fake device: one row per cycle with the
// telemetry of that cycle, the first exchange enabling and the last one switching the drive off
// (0 V, disable) however the run ends (completed, Ctrl-C, a fault, the tracker's refusal, a
// device error), the row format, and the settings refused before anything is sent.
#include "track/track_run.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "../fake_device.h"

namespace swum::host {
namespace {

using test::FakeDevice;

FakeDevice lockstep_device() {
  FakeDevice d;
  d.lockstep_mode = true;
  d.read_step_s = 0.0;  // like swum-emu in lockstep: time moves only when stepped
  return d;
}

TrackRunSettings settings_for(TrackMethod method, double duration_s) {
  TrackRunSettings s;
  s.tracker.method = method;
  s.amplitude_v = 100.0;  // the fake's peak: 40400 Hz
  s.duration_s = duration_s;
  s.cycle_s = 0.02;
  return s;
}

struct TrackRun {
  std::vector<TrackRow> rows;
  std::vector<std::string> events;
  TrackRunResult result;
};

TrackRun run(FakeDevice& device, const TrackRunSettings& s, std::function<bool(const TrackRun&)> stop = {}) {
  TrackRun r;
  TrackRunHooks hooks;
  hooks.on_row = [&r](const TrackRow& row) { r.rows.push_back(row); };
  hooks.on_event = [&r](const std::string& line) { r.events.push_back(line); };
  if (stop) hooks.stop_requested = [&r, stop] { return stop(r); };
  r.result = run_track(device, s, hooks);
  return r;
}

// The drive was switched off by the last exchange: 0 V and disable.
void expect_drive_off_last(const FakeDevice& device) {
  ASSERT_FALSE(device.setpoints.empty());
  EXPECT_EQ(device.setpoints.back().amplitude_v, 0.0);
  ASSERT_FALSE(device.actions.empty());
  EXPECT_EQ(device.actions.back(), DeviceAction::disable);
}

TEST(TrackRun, OneRowPerCycleWithThatCyclesTelemetry) {
  FakeDevice device = lockstep_device();
  const TrackRun r = run(device, settings_for(TrackMethod::fixed, 0.2));
  EXPECT_TRUE(r.result.stop_reason.empty()) << r.result.stop_reason;
  EXPECT_EQ(r.result.cycles, 10u);
  ASSERT_EQ(r.rows.size(), 10u);
  EXPECT_EQ(device.steps, 11);  // + the drive-off step
  EXPECT_EQ(device.total_ticks, 11u * 200u);
  ASSERT_EQ(device.setpoints.size(), 11u);
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    const TrackRow& row = r.rows[i];
    EXPECT_EQ(row.cycle, i);
    EXPECT_NEAR(row.time_s, 0.02 * static_cast<double>(i + 1), 1e-9) << i;  // device time after the cycle
    EXPECT_EQ(row.frequency_hz, device.setpoints[i].frequency_hz) << i;     // what was driven in the cycle
    EXPECT_EQ(device.setpoints[i].amplitude_v, 100.0) << i;
    EXPECT_EQ(device.setpoints[i].phase_deg, 90.0) << i;
    EXPECT_EQ(row.mode, TrackMode::search) << i;  // the cold search takes longer than 10 cycles
    EXPECT_EQ(row.state, 1) << i;
    EXPECT_EQ(row.fault_code, 0) << i;
    EXPECT_GT(row.speed_mm_s, 0.0) << i;
    ASSERT_TRUE(row.electrical.has_value()) << i;
    EXPECT_DOUBLE_EQ(row.electrical->current_a_a, 6e-4 * 100.0) << i;
    EXPECT_DOUBLE_EQ(row.electrical->motional_phase_a_deg, std::clamp((40400.0 - row.frequency_hz) / 10.0, -90.0, 90.0))
        << i;
    ASSERT_TRUE(row.stator_temperature_c.has_value()) << i;
    EXPECT_NEAR(*row.stator_temperature_c, 20.0 + 0.5 * row.time_s, 1e-9) << i;
  }
  // The search steps down from --start-hz by --search-step-hz per cycle.
  EXPECT_EQ(r.rows[0].frequency_hz, 41500.0);
  EXPECT_EQ(r.rows[1].frequency_hz, 41480.0);
  EXPECT_EQ(r.rows[9].frequency_hz, 41320.0);
  // The speed is the fake's first-order response to its resonance curve.
  EXPECT_NEAR(r.rows[9].speed_mm_s, FakeDevice::steady_speed_mm_s(41320.0, 100.0), 1.0);
  // Enabled by the first exchange, kept alive by the others, off by the last.
  EXPECT_EQ(device.actions.front(), DeviceAction::enable);
  for (std::size_t i = 1; i + 1 < device.actions.size(); ++i) EXPECT_EQ(device.actions[i], DeviceAction::keep_alive);
  expect_drive_off_last(device);
  EXPECT_EQ(device.setpoints.back().frequency_hz, r.result.final_frequency_hz);
  EXPECT_EQ(device.state, 0);
  EXPECT_EQ(device.faults_tripped, 0);  // every cycle fed the watchdog
  ASSERT_FALSE(r.events.empty());
  EXPECT_EQ(r.events.front(), "search for the speed peak down from 41500 Hz");
}

TEST(TrackRun, SpeedSearchFindsTheFakesPeakAndHoldsTheMarginAboveIt) {
  FakeDevice device = lockstep_device();
  const TrackRun r = run(device, settings_for(TrackMethod::fixed, 3.0));
  EXPECT_TRUE(r.result.stop_reason.empty()) << r.result.stop_reason;
  ASSERT_EQ(r.rows.size(), 150u);
  ASSERT_TRUE(r.result.peak_hz.has_value());
  EXPECT_NEAR(*r.result.peak_hz, 40400.0, 40.0);
  EXPECT_EQ(r.result.final_frequency_hz, *r.result.peak_hz + 100.0);
  EXPECT_EQ(r.rows.back().mode, TrackMode::hold);
  EXPECT_EQ(r.rows.back().frequency_hz, r.result.final_frequency_hz);
  EXPECT_EQ(r.result.collapses, 0);
  expect_drive_off_last(device);
}

TEST(TrackRun, PhaseMethodCalibratesItsSetPointAndLocks) {
  FakeDevice device = lockstep_device();
  const TrackRun r = run(device, settings_for(TrackMethod::phase, 3.0));
  EXPECT_TRUE(r.result.stop_reason.empty()) << r.result.stop_reason;
  ASSERT_TRUE(r.result.peak_hz.has_value());
  ASSERT_TRUE(r.result.phase_setpoint_deg.has_value());
  // The fake's motional phase is (peak - f) / 10 deg: about -10 deg at peak + 100 Hz.
  EXPECT_NEAR(*r.result.phase_setpoint_deg, (40400.0 - (*r.result.peak_hz + 100.0)) / 10.0, 0.5);
  EXPECT_EQ(r.rows.back().mode, TrackMode::lock);
  EXPECT_NEAR(r.result.final_frequency_hz, *r.result.peak_hz + 100.0, 5.0);
  expect_drive_off_last(device);
}

TEST(TrackRun, CtrlCStopsBeforeTheNextCycleWithTheDriveOff) {
  FakeDevice device = lockstep_device();
  const TrackRun r = run(device, settings_for(TrackMethod::speed, 1.0),
                         [](const TrackRun& so_far) { return so_far.rows.size() >= 3; });
  EXPECT_EQ(r.result.stop_reason, "interrupted");
  EXPECT_EQ(r.result.cycles, 3u);
  EXPECT_EQ(r.rows.size(), 3u);
  EXPECT_EQ(device.steps, 4);
  expect_drive_off_last(device);
  EXPECT_EQ(device.state, 0);
  // Asked before the first cycle: no row, the drive still switched off.
  FakeDevice early = lockstep_device();
  const TrackRun none = run(early, settings_for(TrackMethod::speed, 1.0), [](const TrackRun&) { return true; });
  EXPECT_EQ(none.result.stop_reason, "interrupted");
  EXPECT_EQ(none.result.cycles, 0u);
  EXPECT_TRUE(none.rows.empty());
  EXPECT_EQ(early.steps, 1);
  expect_drive_off_last(early);
  EXPECT_EQ(early.state, 0);
}

TEST(TrackRun, AFaultStopsTheRunNamingTheFaultAndTheCycle) {
  FakeDevice device = lockstep_device();
  device.fault_schedule = {{0.1, 3}};  // at the device time after cycle 4
  const TrackRun r = run(device, settings_for(TrackMethod::speed, 1.0));
  EXPECT_EQ(r.result.stop_reason, "over-current (code 3) at cycle 4");
  ASSERT_EQ(r.rows.size(), 5u);
  EXPECT_EQ(r.result.cycles, 5u);
  EXPECT_EQ(r.rows.back().state, 2);
  EXPECT_EQ(r.rows.back().fault_code, 3);
  EXPECT_EQ(r.rows[3].state, 1);
  expect_drive_off_last(device);
  EXPECT_EQ(std::count(device.actions.begin(), device.actions.end(), DeviceAction::reset_fault), 0);
  // A code the protocol does not name.
  FakeDevice other = lockstep_device();
  other.fault_schedule = {{0.02, 77}};
  EXPECT_EQ(run(other, settings_for(TrackMethod::speed, 1.0)).result.stop_reason, "fault (code 77) at cycle 0");
  expect_drive_off_last(other);
}

// Accepts every command but enable (an enable line held low).
class NeverEnables : public FakeDevice {
 public:
  int enable_requests = 0;
  void command(DeviceAction a) override {
    if (a == DeviceAction::enable) {
      ++enable_requests;
    } else {
      FakeDevice::command(a);
    }
  }
};

// A board that is not enabled is asked again each cycle (a wall-time board applies the enable a
// tick after it reads it); after enable_cycles more the run stops.
TEST(TrackRun, ADeviceThatIsNotEnabledStopsTheRun) {
  NeverEnables device;
  device.lockstep_mode = true;
  device.read_step_s = 0.0;
  TrackRunSettings s = settings_for(TrackMethod::speed, 1.0);
  s.enable_cycles = 5;
  const TrackRun r = run(device, s);
  EXPECT_EQ(r.result.stop_reason, "the device is not enabled after 5 cycles (cycle 5; enable line low?)");
  EXPECT_EQ(r.rows.size(), 6u);
  EXPECT_EQ(device.enable_requests, 6) << "the enable is asked for in every cycle";
  expect_drive_off_last(device);
}

// The DeviceError run_track rethrows and the rows before it.
struct Failed {
  std::string error;
  std::size_t rows = 0;
};

Failed run_until_error(FakeDevice& device) {
  Failed f;
  TrackRunHooks hooks;
  hooks.on_row = [&f](const TrackRow&) { ++f.rows; };
  try {
    (void)run_track(device, settings_for(TrackMethod::speed, 1.0), hooks);
    ADD_FAILURE() << "no error";
  } catch (const DeviceError& e) {
    f.error = e.what();
  }
  return f;
}

TEST(TrackRun, ADeviceErrorIsRethrownAfterTheDriveOff) {
  // The device fails one exchange and answers the next: the drive-off reaches it.
  FakeDevice device = lockstep_device();
  device.on_read = [](int reads) {
    if (reads == 6) throw DeviceError("fake: timeout");
  };
  const Failed f = run_until_error(device);
  EXPECT_EQ(f.error, "fake: timeout");
  EXPECT_EQ(f.rows, 5u);
  EXPECT_EQ(device.steps, 7);  // 6 cycles (the last failed) + the drive-off
  expect_drive_off_last(device);
  EXPECT_EQ(device.state, 0);
  // The link stays down: the drive-off is attempted, its error swallowed, the first one reported.
  FakeDevice broken = lockstep_device();
  broken.fail_after_reads = 5;
  const Failed b = run_until_error(broken);
  EXPECT_EQ(b.error, "fake: link down");
  EXPECT_EQ(b.rows, 5u);
  EXPECT_EQ(broken.steps, 7);
  expect_drive_off_last(broken);
}

TEST(TrackRun, PhaseMethodWithoutTheElectricalPortStopsWithOneLine) {
  const std::string reason = "--method phase: the device does not report the motional phase (electrical port)";
  // Set-point calibrated: the cold speed search runs, the settle needs the phase.
  FakeDevice device = lockstep_device();
  device.electrical_port = false;
  const TrackRun r = run(device, settings_for(TrackMethod::phase, 3.0));
  EXPECT_EQ(r.result.stop_reason, reason);
  ASSERT_FALSE(r.rows.empty());
  EXPECT_LT(r.rows.size(), 150u);
  EXPECT_EQ(r.rows.back().mode, TrackMode::settle);
  for (const TrackRow& row : r.rows) {
    EXPECT_FALSE(row.electrical.has_value());
    EXPECT_FALSE(row.stator_temperature_c.has_value());
  }
  expect_drive_off_last(device);
  EXPECT_EQ(device.state, 0);
  // Set-point given: the approach needs the phase after the first cycle.
  FakeDevice given = lockstep_device();
  given.electrical_port = false;
  TrackRunSettings s = settings_for(TrackMethod::phase, 3.0);
  s.tracker.phase_setpoint_deg = -10.0;
  const TrackRun g = run(given, s);
  EXPECT_EQ(g.result.stop_reason, reason);
  EXPECT_EQ(g.rows.size(), 1u);
  EXPECT_EQ(g.rows.front().mode, TrackMode::approach);
  expect_drive_off_last(given);
  // Speed and fixed do not need it.
  FakeDevice speed_only = lockstep_device();
  speed_only.electrical_port = false;
  EXPECT_TRUE(run(speed_only, settings_for(TrackMethod::speed, 3.0)).result.stop_reason.empty());
}

TEST(TrackRun, WallTimeDeviceIsReadOncePerCycle) {
  FakeDevice device;  // not lockstep: set-point + read per cycle on the host clock
  const TrackRun r = run(device, settings_for(TrackMethod::speed, 0.1));
  EXPECT_TRUE(r.result.stop_reason.empty()) << r.result.stop_reason;
  EXPECT_EQ(r.rows.size(), 5u);
  EXPECT_EQ(device.steps, 0);
  EXPECT_EQ(device.reads, 6);  // + the drive-off
  EXPECT_EQ(device.actions.front(), DeviceAction::enable);
  expect_drive_off_last(device);
  EXPECT_EQ(device.state, 0);
}

TEST(TrackRun, RowsHaveFixedPrecisionAndEmptyElectricalCellsWhenAbsent) {
  TrackRow row;
  row.cycle = 7;
  row.time_s = 0.14;
  row.mode = TrackMode::lock;
  row.frequency_hz = 39512.3456;
  row.speed_mm_s = -123.4567;
  row.state = 1;
  row.fault_code = 0;
  EXPECT_EQ(format_track_row(row), "7,0.140000,lock,39512.346,-123.457,,,,,,,1,0\n");
  row.stator_temperature_c = 27.12345;
  EXPECT_EQ(format_track_row(row), "7,0.140000,lock,39512.346,-123.457,,,,,,27.123,1,0\n");
  row.electrical = protocol::ElectricalValues{0.24, 0.2352, 60.0, 59.0, -12.3456, -11.0, 8.0, 7.6};
  EXPECT_EQ(format_track_row(row),
            "7,0.140000,lock,39512.346,-123.457,-12.346,60.000,0.240000,0.235200,15.6000,27.123,1,0\n");
  row.stator_temperature_c.reset();
  row.mode = TrackMode::recover;
  row.state = 2;
  row.fault_code = 4;
  EXPECT_EQ(format_track_row(row),
            "7,0.140000,recover,39512.346,-123.457,-12.346,60.000,0.240000,0.235200,15.6000,,2,4\n");
  // Every row has the header's cell count.
  const auto cells = [](const std::string& line) { return std::count(line.begin(), line.end(), ',') + 1; };
  EXPECT_EQ(cells(format_track_row(TrackRow{})), cells(kTrackCsvHeader));
  // Whatever a device reports: a current of 1e300 A is 308 characters through %.6f, and the row
  // keeps every cell and its newline.
  row.electrical->current_b_a = 1e300;
  const std::string huge = format_track_row(row);
  EXPECT_GT(huge.size(), 310u);  // the electrical cells alone were cut at 159 characters
  EXPECT_EQ(cells(huge), cells(kTrackCsvHeader));
  EXPECT_EQ(huge.substr(huge.size() - 5), ",2,4\n");
  EXPECT_EQ(cells(format_track_row(row)), cells(kTrackCsvHeader));
}

TEST(TrackRun, BadSettingsAreRefusedNamingTheOptionBeforeAnythingIsSent) {
  struct Bad {
    std::function<void(TrackRunSettings&)> change;
    std::string message;
  };
  const std::vector<Bad> cases = {
      {[](TrackRunSettings& s) { s.amplitude_v = 0.0; }, "--amplitude-v: must be in (0, 10000]"},
      {[](TrackRunSettings& s) { s.amplitude_v = 10001.0; }, "--amplitude-v: must be in (0, 10000]"},
      {[](TrackRunSettings& s) { s.amplitude_v = std::nan(""); }, "--amplitude-v: must be in (0, 10000]"},
      {[](TrackRunSettings& s) { s.drive_phase_deg = 181.0; },
       "--drive-phase-deg: must be in -180..180 and not 0 (its sign is the direction)"},
      {[](TrackRunSettings& s) { s.cycle_s = 0.0; }, "--cycle-ms: must be within (0, 10000]"},
      {[](TrackRunSettings& s) { s.duration_s = 0.01; }, "--duration-s: must be at least one cycle and <= 1e6 s"},
      {[](TrackRunSettings& s) { s.tick_hz = 0.0; }, "--tick-hz: must be in (0, 1e6]"},
      {[](TrackRunSettings& s) { s.tracker.margin_hz = -1.0; }, "--margin-hz: -1 outside 0..5000"},
      {[](TrackRunSettings& s) { s.tracker.start_hz = 60000.0; },
       "--start-hz: 60000 outside --min-frequency-hz..--max-frequency-hz"},
      {[](TrackRunSettings& s) { s.tracker.phase_setpoint_deg = 200.0; },
       "--motional-phase-deg: 200 outside -90..30 (above +30 deg the motional phase lies below the speed peak)"},
      {[](TrackRunSettings& s) { s.tracker.phase_setpoint_deg = 45.0; },
       "--motional-phase-deg: 45 outside -90..30 (above +30 deg the motional phase lies below the speed peak)"},
      {[](TrackRunSettings& s) { s.drive_phase_deg = -90.0; },
       "--method phase: only the forward drive (--drive-phase-deg > 0) is characterised: phase A's motional "
       "phase sits 40 deg lower when reversed (docs/host.md)"},
      // In lockstep a cycle must be a whole number of ticks.
      {[](TrackRunSettings& s) { s.cycle_s = 0.00015; },
       "--cycle-ms: 0.150000 ms is not a whole number of ticks in 1..65535 at --tick-hz 10000.000000"},
  };
  for (const Bad& bad : cases) {
    FakeDevice device = lockstep_device();
    TrackRunSettings s = settings_for(TrackMethod::phase, 1.0);
    bad.change(s);
    try {
      (void)run_track(device, s, {});
      ADD_FAILURE() << "accepted: " << bad.message;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), bad.message);
    }
    EXPECT_TRUE(device.actions.empty()) << bad.message;
    EXPECT_TRUE(device.setpoints.empty()) << bad.message;
    EXPECT_EQ(device.reads, 0) << bad.message;
  }
}

}  // namespace
}  // namespace swum::host
