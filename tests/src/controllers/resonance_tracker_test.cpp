// The tracker's decisions (src/controllers/resonance_tracker.h) against a small softening plant with
// a fold: the speed peak at fp, a jump down below fp - 150 Hz that holds until the drive goes
// above fp + 300 Hz (hysteresis), and the motional phase crossing 0 at fp + 110 Hz with the
// calibrated motor's slope (-0.07 deg/Hz; docs/model.md "Electrical port"). The physics of a
// real run (the emulator, the thermal motor, ten minutes) is in tests/host/track_thermal.py.
#include "controllers/resonance_tracker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "allocation_count.h"

namespace swum {
namespace {

struct Plant {
  std::function<double(double)> peak_hz;  // fp(t)
  bool collapsed = false;
  double collapsed_phase_deg = -160.0;  // the motional phase on the lower branch
  TrackSample sample(double f, double t) {
    const double fp = peak_hz(t);
    if (f < fp - 150.0) collapsed = true;
    if (collapsed && f > fp + 300.0) collapsed = false;
    const double x = (f - fp) / 400.0;
    TrackSample s;
    s.time_s = t;
    s.speed_mm_s = collapsed ? -300.0 : 800.0 / (1.0 + x * x);
    s.motional_phase_deg = collapsed ? -160.0 : -180.0 / std::numbers::pi * std::atan((f - fp - 110.0) / 800.0);
    return s;
  }
};

struct Trace {
  std::vector<double> time_s, frequency_hz, peak_hz;
  std::vector<TrackMode> mode;
};

constexpr double kCycleS = 0.02;

Trace run(ResonanceTracker& tracker, Plant& plant, double duration_s, bool hide_speed = false) {
  Trace r;
  double f = tracker.start().frequency_hz;
  for (double t = kCycleS; t <= duration_s + 1e-9; t += kCycleS) {
    TrackSample s = plant.sample(f, t);
    if (hide_speed) s.speed_mm_s = std::numeric_limits<double>::quiet_NaN();
    const TrackDecision d = tracker.next(s);
    f = d.frequency_hz;
    r.time_s.push_back(t);
    r.frequency_hz.push_back(f);
    r.peak_hz.push_back(plant.peak_hz(t));
    r.mode.push_back(d.mode);
  }
  return r;
}

TrackSettings settings(TrackMethod method) {
  TrackSettings s;
  s.method = method;
  return s;
}

// After the first peak is known, the drive stays within `tolerance` of peak + margin and never
// at or below the peak.
void expect_follows(const Trace& r, double margin_hz, double tolerance_hz, double from_s) {
  int checked = 0;
  for (std::size_t i = 0; i < r.time_s.size(); ++i) {
    if (r.time_s[i] < from_s || r.mode[i] == TrackMode::search) continue;
    EXPECT_NEAR(r.frequency_hz[i], r.peak_hz[i] + margin_hz, tolerance_hz) << "t = " << r.time_s[i];
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(ResonanceTracker, SpeedSearchFindsThePeakAndHoldsTheMargin) {
  Plant plant{[](double) { return 39450.0; }};
  ResonanceTracker tracker(settings(TrackMethod::speed));
  const Trace r = run(tracker, plant, 20.0);
  ASSERT_TRUE(tracker.peak_hz());
  EXPECT_NEAR(*tracker.peak_hz(), 39450.0, 20.0);
  expect_follows(r, 100.0, 25.0, 5.0);
  EXPECT_EQ(tracker.collapses(), 0);
  EXPECT_FALSE(plant.collapsed);
}

// The resonance falls by 450 Hz with a 30 s time constant (the thermal motor at 400 V): the
// periodic searches keep the drive at peak + margin, within the drift of one probe interval.
TEST(ResonanceTracker, SpeedFollowsAResonanceFallingWithTemperature) {
  Plant plant{[](double t) { return 39450.0 - 450.0 * (1.0 - std::exp(-t / 30.0)); }};
  ResonanceTracker tracker(settings(TrackMethod::speed));
  const Trace r = run(tracker, plant, 120.0);
  expect_follows(r, 100.0, 60.0, 5.0);
  EXPECT_EQ(tracker.collapses(), 0);
}

// A resonance moving up, towards and past the operating point, must not pull the drive into the
// fold: each search sees the speed fall at once and moves the operating point up.
TEST(ResonanceTracker, SpeedFollowsAResonanceMovingUp) {
  Plant plant{[](double t) { return 39450.0 + 300.0 * (1.0 - std::exp(-t / 10.0)); }};
  ResonanceTracker tracker(settings(TrackMethod::speed));
  const Trace r = run(tracker, plant, 60.0);
  EXPECT_EQ(tracker.collapses(), 0);
  EXPECT_FALSE(plant.collapsed);
  expect_follows(r, 100.0, 60.0, 40.0);
}

TEST(ResonanceTracker, PhaseLockCalibratesOnceAndFollowsTheDrift) {
  Plant plant{[](double t) { return 39450.0 - 450.0 * (1.0 - std::exp(-t / 30.0)); }};
  ResonanceTracker tracker(settings(TrackMethod::phase));
  const Trace r = run(tracker, plant, 120.0);
  ASSERT_TRUE(tracker.phase_setpoint_deg());
  // Set-point measured at the cold peak + 100 Hz: the plant's phase there is about +0.7 deg.
  EXPECT_NEAR(*tracker.phase_setpoint_deg(), 180.0 / std::numbers::pi * std::atan(10.0 / 800.0), 1.5);
  expect_follows(r, 100.0, 30.0, 5.0);
  EXPECT_EQ(tracker.collapses(), 0);
}

// With --motional-phase-deg the speed is never read (a board without a speed sensor): NaN speeds change
// nothing.
TEST(ResonanceTracker, PhaseWithASetpointNeverReadsTheSpeed) {
  Plant plant{[](double t) { return 39450.0 - 450.0 * (1.0 - std::exp(-t / 30.0)); }};
  TrackSettings s = settings(TrackMethod::phase);
  s.phase_setpoint_deg = 180.0 / std::numbers::pi * std::atan(10.0 / 800.0);  // phase at peak + 100 Hz
  ResonanceTracker tracker(s);
  const Trace r = run(tracker, plant, 60.0, /*hide_speed=*/true);
  expect_follows(r, 100.0, 30.0, 10.0);
  EXPECT_FALSE(tracker.peak_hz());  // no search ran
}

// A disturbance throws the motor onto the lower branch: the phase jumps, the tracker goes up past
// the jump-back point and locks again from above.
TEST(ResonanceTracker, PhaseRecoversFromACollapse) {
  Plant plant{[](double) { return 39450.0; }};
  ResonanceTracker tracker(settings(TrackMethod::phase));
  (void)run(tracker, plant, 10.0);
  plant.collapsed = true;  // e.g. a load step knocked it down
  Trace r;
  double f = tracker.frequency_hz();
  bool recovered = false;
  for (double t = 10.0 + kCycleS; t <= 30.0; t += kCycleS) {
    const TrackDecision d = tracker.next(plant.sample(f, t));
    f = d.frequency_hz;
    if (t > 25.0) {
      EXPECT_EQ(d.mode, TrackMode::lock);
      EXPECT_NEAR(f, 39550.0, 15.0);
      recovered = true;
    }
  }
  EXPECT_TRUE(recovered);
  EXPECT_EQ(tracker.collapses(), 1);
  EXPECT_FALSE(plant.collapsed);
}

// A cycle without a phase reading while recovering to the set-point (e.g. a lost electrical
// frame) ends the run with a status; it is never read from an empty optional.
TEST(ResonanceTracker, PhaseRecoveryWithoutThePhaseEndsWithAStatus) {
  Plant plant{[](double) { return 39450.0; }};
  ResonanceTracker tracker(settings(TrackMethod::phase));
  (void)run(tracker, plant, 10.0);
  ASSERT_TRUE(tracker.phase_setpoint_deg());
  plant.collapsed = true;
  const TrackDecision collapsed = tracker.next(plant.sample(tracker.frequency_hz(), 10.0 + kCycleS));
  ASSERT_EQ(collapsed.mode, TrackMode::recover);
  TrackSample no_phase = plant.sample(collapsed.frequency_hz, 10.0 + 2 * kCycleS);
  no_phase.motional_phase_deg.reset();
  const TrackDecision d = tracker.next(no_phase);
  EXPECT_EQ(d.status, TrackStatus::no_phase_reading);
  EXPECT_EQ(d.frequency_hz, collapsed.frequency_hz);
}

// Ten seconds of running, then the plant knocked onto its lower branch (e.g. a load step) and
// run on to t = 30 s: the frequency the tracker ends at.
double collapse_and_run_on(ResonanceTracker& tracker, Plant& plant) {
  (void)run(tracker, plant, 10.0);
  plant.collapsed = true;
  double f = tracker.frequency_hz();
  for (double t = 10.0 + kCycleS; t <= 30.0; t += kCycleS) f = tracker.next(plant.sample(f, t)).frequency_hz;
  return f;
}

// A lower branch whose phase stays within the phase limit of the set-point (seen on the reverse
// drive: +14 deg against a set-point near 0): with a calibrated set-point the speed is read too,
// and its collapse is caught.
TEST(ResonanceTracker, PhaseLockCatchesACollapseThePhaseHides) {
  Plant plant{[](double) { return 39450.0; }};
  plant.collapsed_phase_deg = 14.0;
  ResonanceTracker tracker(settings(TrackMethod::phase));
  const double f = collapse_and_run_on(tracker, plant);
  EXPECT_EQ(tracker.collapses(), 1);
  EXPECT_FALSE(plant.collapsed);
  EXPECT_NEAR(f, 39550.0, 15.0);
}

// A margin the motor cannot hold (here: the plant collapses whenever the drive is within 200 Hz
// of the peak) ends the run with an error instead of cycling through the fold forever.
TEST(ResonanceTracker, RepeatedCollapsesEndTheRun) {
  Plant plant{[](double) { return 39450.0; }};
  TrackSettings s = settings(TrackMethod::speed);
  s.max_collapses = 3;
  ResonanceTracker tracker(s);
  double f = tracker.start().frequency_hz;
  bool ended = false;
  for (double t = kCycleS; t <= 120.0 && !ended; t += kCycleS) {
    TrackSample sample = plant.sample(f, t);
    if (f < 39650.0) {  // this motor collapses 200 Hz above its peak
      plant.collapsed = true;
      sample = plant.sample(f, t);
    }
    const TrackDecision d = tracker.next(sample);
    if (d.status != TrackStatus::ok) {
      ended = true;
      EXPECT_EQ(d.status, TrackStatus::too_many_collapses);
      EXPECT_EQ(d.collapses, 4);
      EXPECT_EQ(d.frequency_hz, f);  // no new frequency: the run ends where it was
      const std::string text = failure_text(d);
      EXPECT_EQ(text.rfind("collapsed 4 times (last at ", 0), 0u) << text;
      EXPECT_NE(text.find("): the set-point or margin cannot be held; drive off"), std::string::npos) << text;
    } else {
      f = d.frequency_hz;
    }
  }
  EXPECT_TRUE(ended);
}

TEST(ResonanceTracker, SpeedRecoversFromACollapse) {
  Plant plant{[](double) { return 39450.0; }};
  ResonanceTracker tracker(settings(TrackMethod::speed));
  const double f = collapse_and_run_on(tracker, plant);
  EXPECT_EQ(tracker.collapses(), 1);
  EXPECT_FALSE(plant.collapsed);
  EXPECT_NEAR(f, 39550.0, 25.0);
}

// The baseline: one cold search, then the frequency never moves, whatever the drift.
TEST(ResonanceTracker, FixedHoldsTheColdPick) {
  Plant plant{[](double t) { return 39450.0 - 450.0 * (1.0 - std::exp(-t / 30.0)); }};
  ResonanceTracker tracker(settings(TrackMethod::fixed));
  const Trace r = run(tracker, plant, 60.0);
  ASSERT_TRUE(tracker.peak_hz());
  const double held = r.frequency_hz.back();
  EXPECT_NEAR(held, *tracker.peak_hz() + 100.0, 1e-9);
  for (std::size_t i = 0; i < r.time_s.size(); ++i) {
    if (r.time_s[i] > 5.0) {
      EXPECT_EQ(r.frequency_hz[i], held);
    }
  }
}

TEST(ResonanceTracker, PhaseMethodNeedsThePhase) {
  ResonanceTracker tracker([] {
    TrackSettings s;
    s.phase_setpoint_deg = 0.0;
    return s;
  }());
  (void)tracker.start();
  TrackSample s;
  s.speed_mm_s = 100.0;
  const TrackDecision d = tracker.next(s);
  EXPECT_EQ(d.status, TrackStatus::no_phase_reading);
  EXPECT_EQ(failure_text(d), "--method phase: the device does not report the motional phase (electrical port)");
}

// Each event's line, as `swum track` logs it (docs/host.md, "swum track"): the numbers of the
// event in the words the log has always used.
TEST(ResonanceTracker, EventsReadAsOneLineEach) {
  TrackEvent e;
  EXPECT_EQ(describe(e), "");
  e.kind = TrackEventKind::search;
  e.from_hz = 41500.0;
  EXPECT_EQ(describe(e), "search for the speed peak down from 41500 Hz");
  e.kind = TrackEventKind::approach;
  e.setpoint_deg = 12.5;
  EXPECT_EQ(describe(e), "approach from 41500 Hz to the phase set-point 12.5 deg");
  e.kind = TrackEventKind::peak;
  e.peak_hz = 39450.0;
  e.operating_hz = 39550.0;
  e.peak_reason = PeakReason::no_higher_speed;
  EXPECT_EQ(describe(e), "peak 39450 Hz (no higher speed in the last steps), operating point 39550 Hz");
  e.kind = TrackEventKind::collapse;
  e.from_hz = 39500.0;
  e.to_hz = 40150.0;
  e.time_s = 12.25;
  e.cause = CollapseCause::hold_speed;
  e.speed_mm_s = 20.0;
  e.share = 0.5;
  e.reference_mm_s = 80.0;
  EXPECT_EQ(describe(e),
            "collapse at 39500 Hz (speed 20 mm/s below 0.5 x 80 mm/s, t = 12.25 s): up to 40150 Hz, approaching "
            "again from above");
  e.cause = CollapseCause::lock_phase;
  e.phase_deg = 75.0;
  e.error_deg = 62.5;
  EXPECT_EQ(describe(e),
            "collapse at 39500 Hz (phase 75 deg (62.5 deg off the set-point), speed 20 mm/s, t = 12.25 s): up to "
            "40150 Hz, approaching again from above");
  e.kind = TrackEventKind::setpoint_measured;
  EXPECT_EQ(describe(e), "phase set-point 12.5 deg (measured at 39550 Hz)");
  e.kind = TrackEventKind::setpoint_reached;
  EXPECT_EQ(describe(e), "phase set-point reached at 39500 Hz");
}

// A cycle's decision allocates nothing, whatever happens in it: searches, peaks, locks, set-points,
// collapses, recoveries and the end of a run, for each method (the plant is pushed onto its lower
// branch twice).
TEST(ResonanceTracker, DecisionsAllocateNothing) {
  for (const TrackMethod method : {TrackMethod::speed, TrackMethod::phase, TrackMethod::fixed}) {
    SCOPED_TRACE("method " + std::to_string(static_cast<int>(method)));
    Plant plant{[](double t) { return 39450.0 - 300.0 * (1.0 - std::exp(-t / 20.0)); }};
    TrackSettings s = settings(method);
    s.max_collapses = 1;
    ResonanceTracker tracker(s);
    double f = tracker.start().frequency_hz;
    int events = 0;
    TrackStatus last = TrackStatus::ok;
    const long before = test::allocation_count();
    for (int cycle = 1; cycle <= 6000 && last == TrackStatus::ok; ++cycle) {
      const double t = cycle * kCycleS;
      if (cycle == 2000 || cycle == 4000) plant.collapsed = true;  // a disturbance
      const TrackDecision d = tracker.next(plant.sample(f, t));
      f = d.frequency_hz;
      last = d.status;
      if (d.event.kind != TrackEventKind::none) ++events;
    }
    EXPECT_EQ(test::allocation_count() - before, 0);
    EXPECT_GE(events, 1);  // at least the peak
    if (method != TrackMethod::fixed) {
      // The second disturbance is one collapse too many: the failure path is covered too (the
      // fixed frequency sits far enough above the drifting peak for the plant to recover alone).
      EXPECT_EQ(tracker.collapses(), 2);
      EXPECT_EQ(last, TrackStatus::too_many_collapses);
    }
  }
}

TEST(ResonanceTracker, SettingsAreChecked) {
  TrackSettings s;
  EXPECT_EQ(check(s), "");
  s.margin_hz = -1.0;
  EXPECT_EQ(check(s), "--margin-hz: -1 outside 0..5000");
  s = TrackSettings{};
  s.start_hz = 60000.0;
  EXPECT_EQ(check(s), "--start-hz: 60000 outside --min-frequency-hz..--max-frequency-hz");
  s = TrackSettings{};
  s.phase_setpoint_deg = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(check(s),
            "--motional-phase-deg: nan outside -90..30 (above +30 deg the motional phase lies below the speed peak)");
  s.phase_setpoint_deg = 45.0;
  EXPECT_NE(check(s), "");
  EXPECT_THROW(ResonanceTracker{s}, std::invalid_argument);
}

}  // namespace
}  // namespace swum
