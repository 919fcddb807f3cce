// `swum track`'s decision per control cycle (docs/host.md, "swum track"): keep the drive a
// margin above the softening speed peak while the resonance moves with temperature and load,
// never dwelling below the peak, where the speed collapses. Pure: one telemetry sample in, the
// next frequency out; the caller does the device exchange and the log (host/track/track_run.cpp).
// A cycle's decision allocates nothing and throws nothing, so that a drive may run it in its
// real-time tick: what happened is a TrackEvent of numbers, what went wrong a TrackStatus, and
// both become text only where a log is written (describe(), failure_text()).
//
// Methods:
//  * speed  - extremum seeking with a margin: a search steps down from the operating point
//             while the speed still rises, takes the best point as the peak and returns to
//             peak + margin; repeated every probe interval, so the operating point follows
//             the peak both ways.
//  * phase  - a phase-locked loop on the motional current's phase of phase A (C0 compensated,
//             what a board with a parallel inductor or a bridge measures): holds the phase the
//             motor shows at peak + margin. The set-point comes from --motional-phase-deg, or from one
//             cold speed search at the start; after that the speed is never read.
//  * fixed  - the baseline: one cold speed search, then the frequency held.
// Collapse (the speed below a share of the last good speed, or for phase the phase off its
// set-point by more than a limit) is left upwards: jump up by the recovery span, then approach
// again from above.
#pragma once

#include <optional>
#include <string>

namespace swum {

enum class TrackMethod { phase, speed, fixed };

struct TrackSettings {
  TrackMethod method = TrackMethod::phase;
  double direction = 1.0;                    // sign of the speed the drive produces (the command: sign of its phase)
  double margin_hz = 100.0;                  // operating point above the peak
  double start_hz = 41500.0;                 // the approach starts here (above the resonance)
  double min_hz = 30000.0;                   // never below (a search that finds no peak stops here)
  double max_hz = 50000.0;                   // never above
  double search_step_hz = 20.0;              // one search step per dwell
  int search_dwell_cycles = 1;               // cycles per search step (the speed is read at the last one)
  int search_patience = 3;                   // steps without a new best that end a search
  double search_drop = 0.003;                // a speed this share below the best ends a search at once
  double probe_interval_s = 2.0;             // speed method: time between searches
  int settle_cycles = 5;                     // cycles at the operating point before a set-point is taken
  std::optional<double> phase_setpoint_deg;  // phase method: none = calibrate by one cold speed search
  double phase_gain_hz_per_deg = 4.0;        // PLL: frequency change per degree of phase error per cycle
  double max_step_hz = 20.0;                 // largest frequency change of the PLL per cycle
  double approach_step_hz = 25.0;            // phase method: descent per cycle until the set-point
  double collapse_share = 0.5;               // speed below this share of the last good one: collapsed
  double phase_collapse_deg = 60.0;          // |phase - set-point| above this: collapsed
  double recovery_hz = 600.0;                // jump above the operating point after a collapse
  int max_collapses = 5;                     // more in one run: the set-point or margin cannot be held (error)
};

// The highest phase set-point accepted: on the calibrated motor phase A's motional phase is
// +8 deg (400 V) and +17 deg (100 V) at the speed peak and rises to +24 deg at the fold; a
// set-point above +30 deg lies below the peak, where the loop would lock on the collapsed side.
inline constexpr double kMaxPhaseSetpointDeg = 30.0;

// One line naming the first bad setting (the command's option name), empty when all are usable.
[[nodiscard]] std::string check(const TrackSettings& settings);

// What the tracker sees after a cycle.
struct TrackSample {
  double time_s = 0.0;
  double speed_mm_s = 0.0;                   // signed; the direction of motion is the drive's
  std::optional<double> motional_phase_deg;  // phase A's motional current vs V_A; none: not reported
};

enum class TrackMode { search, settle, hold, lock, approach, recover };
[[nodiscard]] const char* mode_name(TrackMode mode);

// What happened in a cycle, as numbers; describe() gives its one line for a log.
enum class TrackEventKind {
  none,
  approach,           // phase method with a set-point: from `from_hz` down to `setpoint_deg`
  search,             // a search for the speed peak down from `from_hz`
  peak,               // the peak `peak_hz` found (`peak_reason`), operating point `operating_hz`
  collapse,           // collapsed at `from_hz` (`cause`, `time_s`), up to `to_hz`
  setpoint_measured,  // phase set-point `setpoint_deg`, measured at `operating_hz`
  setpoint_reached,   // the approach reached the phase set-point at `from_hz`
};
enum class PeakReason { speed_fell, no_higher_speed, min_hz_reached };
enum class CollapseCause {
  search_speed,  // `speed_mm_s` below `share` x the search's best `reference_mm_s`
  hold_speed,    // `speed_mm_s` below `share` x the held speed `reference_mm_s`
  lock_phase,    // `phase_deg` (`error_deg` off the set-point), speed `speed_mm_s`
};
struct TrackEvent {
  TrackEventKind kind = TrackEventKind::none;
  double from_hz = 0.0;
  double to_hz = 0.0;
  double peak_hz = 0.0;
  double operating_hz = 0.0;
  double setpoint_deg = 0.0;
  PeakReason peak_reason = PeakReason::speed_fell;
  CollapseCause cause = CollapseCause::hold_speed;
  double time_s = 0.0;
  double speed_mm_s = 0.0;
  double reference_mm_s = 0.0;
  double share = 0.0;
  double phase_deg = 0.0;
  double error_deg = 0.0;
};

// Why a run cannot go on: the caller switches the drive off.
enum class TrackStatus {
  ok,
  too_many_collapses,  // more than max_collapses: the set-point or margin cannot be held
  no_phase_reading,    // the phase method got a sample without the motional phase
};

struct TrackDecision {
  double frequency_hz = 0.0;
  TrackMode mode = TrackMode::search;
  TrackEvent event;                      // kind none: nothing to log
  TrackStatus status = TrackStatus::ok;  // not ok: the run ends (frequency and mode as they were)
  int collapses = 0;                     // with too_many_collapses: how many
};

// The event's one line for a log, empty for none ("peak 39450 Hz (...), operating point 39550 Hz").
[[nodiscard]] std::string describe(const TrackEvent& event);
// A failed decision's one line ("collapsed 4 times (last at ...): ...; drive off"), empty when ok.
[[nodiscard]] std::string failure_text(const TrackDecision& decision);

class ResonanceTracker {
 public:
  explicit ResonanceTracker(const TrackSettings& settings);  // throws std::invalid_argument (check())

  // The frequency of the first cycle.
  [[nodiscard]] TrackDecision start();
  // The telemetry after the last cycle -> the frequency of the next one. Allocates and throws
  // nothing; a phase method without a phase reading, or one collapse too many, returns a status.
  [[nodiscard]] TrackDecision next(const TrackSample& sample);

  [[nodiscard]] std::optional<double> peak_hz() const { return peak_hz_; }
  [[nodiscard]] std::optional<double> phase_setpoint_deg() const { return setpoint_deg_; }
  [[nodiscard]] int collapses() const { return collapses_; }
  [[nodiscard]] double frequency_hz() const { return frequency_hz_; }

 private:
  TrackDecision search_step(const TrackSample& s);
  TrackDecision begin_search(double from_hz);
  TrackDecision found_peak(PeakReason why);
  // `why` carries the cause and its readings; the rest of the event is filled here.
  TrackDecision collapse(const TrackSample& s, TrackEvent why);
  TrackDecision decide(TrackMode mode, const TrackEvent& event = {});
  [[nodiscard]] bool collapsed(const TrackSample& s) const;
  [[nodiscard]] double speed_of(const TrackSample& s) const;  // along the drive direction
  [[nodiscard]] double clamp_hz(double f) const;

  TrackSettings settings_;
  TrackMode mode_ = TrackMode::search;
  double frequency_hz_ = 0.0;
  double operating_hz_ = 0.0;
  std::optional<double> peak_hz_;
  std::optional<double> setpoint_deg_;
  // Search state.
  double best_speed_mm_s_ = 0.0;
  double best_hz_ = 0.0;
  int since_best_ = 0;
  int dwell_ = 0;
  // Settle / hold.
  int settle_left_ = 0;
  double phase_sum_deg_ = 0.0;
  int phase_count_ = 0;
  double next_probe_s_ = 0.0;
  double good_speed_mm_s_ = 0.0;  // the speed the collapse test compares with
  bool searched_once_ = false;
  int collapses_ = 0;
};

}  // namespace swum
