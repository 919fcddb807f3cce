#include "controllers/resonance_tracker.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "formats/number_format.h"
#include "model/machine/electrical.h"

namespace swum {
namespace {

std::string hz(double f) { return format_number(f) + " Hz"; }

const char* peak_reason_text(PeakReason why) {
  switch (why) {
    case PeakReason::speed_fell: return "the speed fell below the best";
    case PeakReason::no_higher_speed: return "no higher speed in the last steps";
    case PeakReason::min_hz_reached: return "--min-frequency-hz reached";
  }
  return "?";
}

// The collapse's cause with its readings ("speed 12 mm/s below 0.5 x 80 mm/s").
std::string cause_text(const TrackEvent& e) {
  switch (e.cause) {
    case CollapseCause::search_speed:
      return "speed " + format_number(e.speed_mm_s) + " mm/s below " + format_number(e.share) + " x the best " +
             format_number(e.reference_mm_s) + " mm/s during the search";
    case CollapseCause::hold_speed:
      return "speed " + format_number(e.speed_mm_s) + " mm/s below " + format_number(e.share) + " x " +
             format_number(e.reference_mm_s) + " mm/s";
    case CollapseCause::lock_phase:
      return "phase " + format_number(e.phase_deg) + " deg (" + format_number(e.error_deg) +
             " deg off the set-point), speed " + format_number(e.speed_mm_s) + " mm/s";
  }
  return "?";
}

TrackEvent event_of(TrackEventKind kind, double from_hz) {
  TrackEvent e;
  e.kind = kind;
  e.from_hz = from_hz;
  return e;
}

}  // namespace

std::string describe(const TrackEvent& e) {
  switch (e.kind) {
    case TrackEventKind::none: return {};
    case TrackEventKind::approach:
      return "approach from " + hz(e.from_hz) + " to the phase set-point " + format_number(e.setpoint_deg) + " deg";
    case TrackEventKind::search: return "search for the speed peak down from " + hz(e.from_hz);
    case TrackEventKind::peak:
      return "peak " + hz(e.peak_hz) + " (" + peak_reason_text(e.peak_reason) + "), operating point " +
             hz(e.operating_hz);
    case TrackEventKind::collapse:
      return "collapse at " + hz(e.from_hz) + " (" + cause_text(e) + ", t = " + format_number(e.time_s) +
             " s): up to " + hz(e.to_hz) + ", approaching again from above";
    case TrackEventKind::setpoint_measured:
      return "phase set-point " + format_number(e.setpoint_deg) + " deg (measured at " + hz(e.operating_hz) + ")";
    case TrackEventKind::setpoint_reached: return "phase set-point reached at " + hz(e.from_hz);
  }
  return {};
}

std::string failure_text(const TrackDecision& d) {
  switch (d.status) {
    case TrackStatus::ok: return {};
    case TrackStatus::too_many_collapses:
      return "collapsed " + std::to_string(d.collapses) + " times (last at " + hz(d.event.from_hz) + ": " +
             cause_text(d.event) + "): the set-point or margin cannot be held; drive off";
    case TrackStatus::no_phase_reading:
      return "--method phase: the device does not report the motional phase (electrical port)";
  }
  return {};
}

std::string check(const TrackSettings& s) {
  auto bad = [](const char* option, double value, const char* range) {
    return std::string(option) + ": " + format_number(value) + " outside " + range;
  };
  if (!(s.margin_hz >= 0.0 && s.margin_hz <= 5000.0)) return bad("--margin-hz", s.margin_hz, "0..5000");
  if (!(s.min_hz >= 1000.0 && s.max_hz <= 200000.0 && s.min_hz < s.max_hz))
    return "--min-frequency-hz/--max-frequency-hz: need 1000 <= min < max <= 200000";
  if (!(s.start_hz >= s.min_hz && s.start_hz <= s.max_hz))
    return bad("--start-hz", s.start_hz, "--min-frequency-hz..--max-frequency-hz");
  if (!(s.search_step_hz > 0.0 && s.search_step_hz <= 1000.0))
    return bad("--search-step-hz", s.search_step_hz, "(0, 1000]");
  if (s.search_dwell_cycles < 1 || s.search_dwell_cycles > 1000) return "--search-dwell-cycles: outside 1..1000";
  if (s.search_patience < 1 || s.search_patience > 100) return "--search-patience: outside 1..100";
  if (!(s.search_drop > 0.0 && s.search_drop < 1.0)) return bad("--search-drop", s.search_drop, "(0, 1)");
  if (!(s.probe_interval_s > 0.0 && s.probe_interval_s <= 1e5))
    return bad("--probe-interval-s", s.probe_interval_s, "(0, 1e5]");
  if (s.settle_cycles < 1 || s.settle_cycles > 10000) return "--settle-cycles: outside 1..10000";
  if (s.phase_setpoint_deg && !(*s.phase_setpoint_deg >= -90.0 && *s.phase_setpoint_deg <= kMaxPhaseSetpointDeg))
    return bad("--motional-phase-deg", *s.phase_setpoint_deg,
               "-90..30 (above +30 deg the motional phase lies below the speed peak)");
  if (!(s.direction == 1.0 || s.direction == -1.0)) return "direction: must be +1 or -1";
  if (s.max_collapses < 0 || s.max_collapses > 1000) return "--max-collapses: outside 0..1000";
  if (!(s.phase_gain_hz_per_deg > 0.0 && s.phase_gain_hz_per_deg <= 1000.0))
    return bad("--phase-gain-hz-per-deg", s.phase_gain_hz_per_deg, "(0, 1000]");
  if (!(s.max_step_hz > 0.0 && s.max_step_hz <= 5000.0)) return bad("--max-step-hz", s.max_step_hz, "(0, 5000]");
  if (!(s.approach_step_hz > 0.0 && s.approach_step_hz <= 5000.0))
    return bad("--approach-step-hz", s.approach_step_hz, "(0, 5000]");
  if (!(s.collapse_share > 0.0 && s.collapse_share < 1.0)) return bad("--collapse-share", s.collapse_share, "(0, 1)");
  if (!(s.phase_collapse_deg > 0.0 && s.phase_collapse_deg <= 180.0))
    return bad("--phase-collapse-deg", s.phase_collapse_deg, "(0, 180]");
  if (!(s.recovery_hz > 0.0 && s.recovery_hz <= 20000.0)) return bad("--recovery-hz", s.recovery_hz, "(0, 20000]");
  return {};
}

const char* mode_name(TrackMode mode) {
  switch (mode) {
    case TrackMode::search: return "search";
    case TrackMode::settle: return "settle";
    case TrackMode::hold: return "hold";
    case TrackMode::lock: return "lock";
    case TrackMode::approach: return "approach";
    case TrackMode::recover: return "recover";
  }
  return "?";
}

ResonanceTracker::ResonanceTracker(const TrackSettings& settings) : settings_(settings) {
  const std::string problem = check(settings_);
  if (!problem.empty()) throw std::invalid_argument(problem);
  if (settings_.phase_setpoint_deg) setpoint_deg_ = *settings_.phase_setpoint_deg;
}

double ResonanceTracker::clamp_hz(double f) const { return std::clamp(f, settings_.min_hz, settings_.max_hz); }

double ResonanceTracker::speed_of(const TrackSample& s) const { return settings_.direction * s.speed_mm_s; }

TrackDecision ResonanceTracker::decide(TrackMode mode, const TrackEvent& event) {
  mode_ = mode;
  return {frequency_hz_, mode, event, TrackStatus::ok, collapses_};
}

TrackDecision ResonanceTracker::start() {
  frequency_hz_ = settings_.start_hz;
  operating_hz_ = settings_.start_hz;
  if (settings_.method == TrackMethod::phase && setpoint_deg_) {
    TrackEvent e = event_of(TrackEventKind::approach, frequency_hz_);
    e.setpoint_deg = *setpoint_deg_;
    return decide(TrackMode::approach, e);
  }
  best_speed_mm_s_ = -1e300;
  best_hz_ = frequency_hz_;
  since_best_ = 0;
  dwell_ = 0;
  return decide(TrackMode::search, event_of(TrackEventKind::search, frequency_hz_));
}

TrackDecision ResonanceTracker::begin_search(double from_hz) {
  // The sample at from_hz is the one just taken (the hold cycle): the search starts below it.
  since_best_ = 0;
  dwell_ = 0;
  best_hz_ = from_hz;
  frequency_hz_ = clamp_hz(from_hz - settings_.search_step_hz);
  return decide(TrackMode::search);
}

TrackDecision ResonanceTracker::found_peak(PeakReason why) {
  peak_hz_ = best_hz_;
  operating_hz_ = clamp_hz(best_hz_ + settings_.margin_hz);
  frequency_hz_ = operating_hz_;  // up from the search: never into the collapse
  settle_left_ = settings_.settle_cycles;
  phase_sum_deg_ = 0.0;
  phase_count_ = 0;
  searched_once_ = true;
  TrackEvent e = event_of(TrackEventKind::peak, frequency_hz_);
  e.peak_hz = best_hz_;
  e.peak_reason = why;
  e.operating_hz = operating_hz_;
  return decide(TrackMode::settle, e);
}

TrackDecision ResonanceTracker::collapse(const TrackSample& s, TrackEvent why) {
  why.kind = TrackEventKind::collapse;
  why.from_hz = frequency_hz_;
  why.time_s = s.time_s;
  why.share = settings_.collapse_share;
  if (++collapses_ > settings_.max_collapses) {
    return {frequency_hz_, mode_, why, TrackStatus::too_many_collapses, collapses_};
  }
  frequency_hz_ = clamp_hz(std::max(frequency_hz_, operating_hz_) + settings_.recovery_hz);
  why.to_hz = frequency_hz_;
  good_speed_mm_s_ = 0.0;  // the mover re-accelerates: no collapse test until a new reference
  return decide(TrackMode::recover, why);
}

bool ResonanceTracker::collapsed(const TrackSample& s) const {
  const bool speed_collapsed = good_speed_mm_s_ > 0.0 && speed_of(s) < settings_.collapse_share * good_speed_mm_s_;
  if (settings_.method == TrackMethod::phase && setpoint_deg_) {
    const bool phase_collapsed = s.motional_phase_deg &&
                                 std::abs(wrap_phase_deg(*s.motional_phase_deg - *setpoint_deg_)) >
                                     settings_.phase_collapse_deg;
    // With --motional-phase-deg the speed is never read (a board without a speed sensor): the phase only.
    return phase_collapsed || (!settings_.phase_setpoint_deg && speed_collapsed);
  }
  return speed_collapsed;
}

TrackDecision ResonanceTracker::search_step(const TrackSample& s) {
  if (++dwell_ < settings_.search_dwell_cycles) return decide(TrackMode::search);
  dwell_ = 0;
  const double v = speed_of(s);
  if (best_speed_mm_s_ > 0.0 && v < settings_.collapse_share * best_speed_mm_s_) {
    // Past the fold within one step: the peak is known, the branch is lost.
    peak_hz_ = best_hz_;
    operating_hz_ = clamp_hz(best_hz_ + settings_.margin_hz);
    searched_once_ = true;
    TrackEvent why;
    why.cause = CollapseCause::search_speed;
    why.speed_mm_s = v;
    why.reference_mm_s = best_speed_mm_s_;
    return collapse(s, why);
  }
  if (v > best_speed_mm_s_) {
    best_speed_mm_s_ = v;
    best_hz_ = frequency_hz_;
    since_best_ = 0;
  } else {
    ++since_best_;
  }
  if (best_speed_mm_s_ > 0.0 && v < (1.0 - settings_.search_drop) * best_speed_mm_s_)
    return found_peak(PeakReason::speed_fell);
  if (since_best_ >= settings_.search_patience) return found_peak(PeakReason::no_higher_speed);
  if (frequency_hz_ - settings_.search_step_hz < settings_.min_hz) return found_peak(PeakReason::min_hz_reached);
  frequency_hz_ -= settings_.search_step_hz;
  return decide(TrackMode::search);
}

TrackDecision ResonanceTracker::next(const TrackSample& s) {
  const bool uses_phase = settings_.method == TrackMethod::phase;
  // Every mode that reads the phase: lock, settle, and the approach down to a set-point (also
  // after a collapse, in recover, once a set-point is known).
  const bool reads_phase = mode_ == TrackMode::lock || mode_ == TrackMode::approach || mode_ == TrackMode::settle ||
                           (mode_ == TrackMode::recover && setpoint_deg_);
  if (uses_phase && reads_phase && !s.motional_phase_deg) {
    return {frequency_hz_, mode_, {}, TrackStatus::no_phase_reading, collapses_};
  }
  switch (mode_) {
    case TrackMode::search: return search_step(s);
    case TrackMode::settle: {
      if (uses_phase && settle_left_ <= (settings_.settle_cycles + 1) / 2) {
        phase_sum_deg_ += *s.motional_phase_deg;  // the second half of the settle cycles
        ++phase_count_;
      }
      if (--settle_left_ > 0) return decide(TrackMode::settle);
      good_speed_mm_s_ = speed_of(s);
      next_probe_s_ = s.time_s + settings_.probe_interval_s;
      if (uses_phase) {
        TrackEvent event;
        if (!setpoint_deg_) {
          setpoint_deg_ = phase_sum_deg_ / phase_count_;
          event.kind = TrackEventKind::setpoint_measured;
          event.setpoint_deg = *setpoint_deg_;
          event.operating_hz = operating_hz_;
        }
        return decide(TrackMode::lock, event);
      }
      return decide(TrackMode::hold);
    }
    case TrackMode::hold: {
      if (collapsed(s)) {
        TrackEvent why;
        why.cause = CollapseCause::hold_speed;
        why.speed_mm_s = speed_of(s);
        why.reference_mm_s = good_speed_mm_s_;
        return collapse(s, why);
      }
      good_speed_mm_s_ += 0.2 * (speed_of(s) - good_speed_mm_s_);  // follows the slow drift
      if (settings_.method == TrackMethod::speed && s.time_s >= next_probe_s_) {
        best_speed_mm_s_ = speed_of(s);
        return begin_search(frequency_hz_);
      }
      return decide(TrackMode::hold);
    }
    case TrackMode::lock: {
      const double error_deg = wrap_phase_deg(*s.motional_phase_deg - *setpoint_deg_);
      if (collapsed(s)) {
        TrackEvent why;
        why.cause = CollapseCause::lock_phase;
        why.phase_deg = *s.motional_phase_deg;
        why.error_deg = error_deg;
        why.speed_mm_s = speed_of(s);
        return collapse(s, why);
      }
      if (!settings_.phase_setpoint_deg) good_speed_mm_s_ += 0.2 * (speed_of(s) - good_speed_mm_s_);
      // Above the resonance the phase falls with frequency: a phase above the set-point means
      // the drive is too low, so the frequency goes up.
      const double step = std::clamp(settings_.phase_gain_hz_per_deg * error_deg, -settings_.max_step_hz,
                                     settings_.max_step_hz);
      frequency_hz_ = clamp_hz(frequency_hz_ + step);
      operating_hz_ = frequency_hz_;
      return decide(TrackMode::lock);
    }
    case TrackMode::approach:
    case TrackMode::recover: {
      if (uses_phase && setpoint_deg_) {
        // Down from above until the phase reaches the set-point, then the loop takes over.
        if (wrap_phase_deg(*s.motional_phase_deg - *setpoint_deg_) >= 0.0 && frequency_hz_ < settings_.max_hz) {
          good_speed_mm_s_ = std::max(0.0, speed_of(s));  // the collapse test's reference from here on
          return decide(TrackMode::lock, event_of(TrackEventKind::setpoint_reached, frequency_hz_));
        }
        frequency_hz_ = clamp_hz(frequency_hz_ - settings_.approach_step_hz);
        operating_hz_ = frequency_hz_;  // a collapse now recovers from here, not from --start-hz
        return decide(mode_);
      }
      // Speed and fixed: down to the operating point, settle, then (speed) search again.
      if (frequency_hz_ - settings_.approach_step_hz > operating_hz_) {
        frequency_hz_ -= settings_.approach_step_hz;
        return decide(mode_);
      }
      frequency_hz_ = operating_hz_;
      settle_left_ = settings_.settle_cycles;
      good_speed_mm_s_ = 0.0;
      return decide(TrackMode::settle);
    }
  }
  return decide(mode_);
}

}  // namespace swum
