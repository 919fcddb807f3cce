#include "core/scenario_player.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace swum::emu {

ScenarioPlayer::ScenarioPlayer(Scenario scenario, double tick_hz)
    : scenario_(std::move(scenario)), tick_hz_(tick_hz), rng_state_(scenario_.seed ^ 0x9E3779B97F4A7C15ULL) {
  active_.reserve(scenario_.events.size() + kMaxActiveFaults);
  now_.started.reserve(scenario_.events.size());
  for (ScenarioEvent& e : runtime_waiting_) e.origin = "http";  // short: no allocation when copied
  for (ScenarioEvent& e : runtime_started_) e.origin = "http";
}

bool ScenarioPlayer::queue_runtime(const RuntimeEvent& event) {
  // Faults and clears only: a load profile keeps a pointer to its event.
  if ((!is_fault(event.type) && event.type != EventType::clear) || runtime_waiting_count_ == runtime_waiting_.size()) {
    ++refused_;
    ++generation_;  // the refusal count is published with the set
    return false;
  }
  ScenarioEvent& e = runtime_waiting_[runtime_waiting_count_++];
  e.type = event.type;
  e.parameters = event.parameters;
  return true;
}

void ScenarioPlayer::active_faults(ActiveFaults& out) const {
  out.generation = generation_;
  out.refused = refused_;
  out.total = static_cast<std::uint32_t>(active_.size());
  out.count = 0;
  for (const Active& a : active_) {
    if (out.count == out.items.size()) break;
    out.items[out.count++] = {a.type, a.start_tick, a.end_tick, a.parameters};
  }
}

std::uint64_t ScenarioPlayer::to_tick(double seconds) const {
  return static_cast<std::uint64_t>(std::llround(seconds * tick_hz_));
}

double ScenarioPlayer::normal() {
  if (spare_normal_) {
    const double z = *spare_normal_;
    spare_normal_.reset();
    return z;
  }
  auto next = [&] {  // splitmix64
    std::uint64_t z = (rng_state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  };
  const double u1 = (static_cast<double>(next() >> 11) + 1.0) * 0x1.0p-53;  // (0, 1]
  const double u2 = static_cast<double>(next() >> 11) * 0x1.0p-53;
  const double r = std::sqrt(-2.0 * std::log(u1));
  spare_normal_ = r * std::sin(2.0 * std::numbers::pi * u2);
  return r * std::cos(2.0 * std::numbers::pi * u2);
}

double ScenarioPlayer::load_at(std::uint64_t tick) const {
  const EventParameters& p = load_event_->parameters;
  const double t_s = static_cast<double>(tick - load_start_tick_) / tick_hz_;
  switch (load_event_->type) {
    case EventType::load_ramp:
      return t_s >= p.duration_s ? p.to_n : load_from_n_ + (p.to_n - load_from_n_) * (t_s / p.duration_s);
    case EventType::load_sine:
      if (p.duration_s > 0.0 && t_s >= p.duration_s) return p.offset_n;
      return p.offset_n + p.amplitude_n * std::sin(2.0 * std::numbers::pi * p.frequency_hz * t_s);
    default: return p.load_n;  // load_step
  }
}

bool ScenarioPlayer::start(const ScenarioEvent& e, std::uint64_t tick, bool runtime) {
  const EventParameters& p = e.parameters;
  switch (e.type) {
    case EventType::load_step:
    case EventType::load_ramp:
    case EventType::load_sine:
      // The load in force at this tick (the previous profile's value here, after any load event
      // earlier at this same tick), not at the last tick asked.
      // Before any profile: the load the host commanded (what the motor carries at this tick).
      load_from_n_ = load_event_ != nullptr ? load_at(tick) : commanded_load_n_;
      load_event_ = &e;
      load_start_tick_ = tick;
      return true;
    case EventType::ambient: now_.ambient_c = p.temperature_c; return true;
    case EventType::modbus_drop: now_.modbus_drops_started += p.count; return true;
    case EventType::clear:  // fault == clear: every fault (run time only; a file's clear names one)
      std::erase_if(active_, [&](const Active& a) {
        const bool cleared = p.fault == EventType::clear || a.type == p.fault;
        if (cleared && a.runtime) --runtime_active_;
        return cleared;
      });
      ++generation_;
      return true;
    default: break;
  }
  // A fault that lasts (until its duration ends or a clear); phase_short and over_temperature
  // have no duration: they hold until cleared.
  const std::uint64_t end = p.duration_s > 0.0 ? tick + std::max<std::uint64_t>(1, to_tick(p.duration_s)) : 0;
  if (runtime) {
    if (runtime_active_ == kMaxActiveFaults) {
      ++refused_;
      ++generation_;  // the refusal count is published with the set
      return false;
    }
    ++runtime_active_;
  }
  if (e.type == EventType::jam) ++now_.jam_generation;
  active_.push_back({e.type, tick, end, p, runtime});
  ++generation_;
  return true;
}

const ScenarioConditions& ScenarioPlayer::at_tick(std::uint64_t tick) {
  now_.started.clear();
  now_.modbus_drops_started = 0;
  const std::size_t before = active_.size();
  std::erase_if(active_, [&](const Active& a) {
    const bool ended = a.end_tick != 0 && tick >= a.end_tick;
    if (ended && a.runtime) --runtime_active_;
    return ended;
  });
  if (active_.size() != before) ++generation_;
  for (; next_ < scenario_.events.size() && to_tick(scenario_.events[next_].at_s) <= tick; ++next_) {
    start(scenario_.events[next_], tick);
    now_.started.push_back(&scenario_.events[next_]);
  }
  // Run-time events after the file's of this tick, in the order they came.
  for (std::size_t i = 0; i < runtime_waiting_count_; ++i) {
    ScenarioEvent& e = runtime_started_[i];
    e.type = runtime_waiting_[i].type;
    e.parameters = runtime_waiting_[i].parameters;
    e.at_s = static_cast<double>(tick) / tick_hz_;
    // Not in `started`: the loop does not log them (a client may send many; the API logs them
    // as it queues them), and a refused one is counted.
    start(e, tick, true);
  }
  runtime_waiting_count_ = 0;
  if (load_event_ != nullptr) now_.load_n = load_at(tick);

  // Faults in force: the last started of each kind wins where they set the same value.
  ScenarioConditions& c = now_;
  bool open_a = false, open_b = false;
  double sag = 1.0;
  c.preload_factor = c.guide_friction_factor = 1.0;
  c.jammed = c.over_current = c.over_temperature = false;
  c.encoder_stuck = c.speed_frozen = c.telemetry_silent = c.can_bus_off = false;
  c.encoder_sigma_um = c.speed_bias_mm_s = c.speed_sigma_mm_s = c.modbus_delay_ms = 0.0;
  for (const Active& a : active_) {
    const EventParameters& p = a.parameters;
    switch (a.type) {
      case EventType::phase_open: (p.phase == Phase::A ? open_a : open_b) = true; break;
      case EventType::phase_short: c.over_current = true; break;
      case EventType::over_temperature: c.over_temperature = true; break;
      case EventType::voltage_sag: sag = p.factor; break;
      case EventType::jam:
        c.jammed = true;
        c.jam_position_um = p.position_um;
        break;
      case EventType::guide_friction: c.guide_friction_factor = p.factor; break;
      case EventType::preload_loss: c.preload_factor = p.factor; break;
      case EventType::encoder_stuck: c.encoder_stuck = true; break;
      case EventType::encoder_noise: c.encoder_sigma_um = p.sigma_um; break;
      case EventType::speed_frozen: c.speed_frozen = true; break;
      case EventType::speed_bias: c.speed_bias_mm_s = p.bias_mm_s; break;
      case EventType::speed_noise: c.speed_sigma_mm_s = p.sigma_mm_s; break;
      case EventType::telemetry_silence: c.telemetry_silent = true; break;
      case EventType::modbus_delay: c.modbus_delay_ms = p.delay_ms; break;
      case EventType::can_bus_off: c.can_bus_off = true; break;
      default: break;
    }
  }
  c.phase_a_gain = open_a ? 0.0 : sag;
  c.phase_b_gain = open_b ? 0.0 : sag;
  return c;
}

}  // namespace swum::emu
