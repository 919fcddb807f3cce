// A scenario's timeline tick by tick (docs/scenarios.md): which load, ambient and faults hold
// during tick k, whose boundary is at k / tick_hz emulated seconds. Pure: no clock, no I/O; the
// emulator core asks at every tick boundary and applies the answer to the model, the amplifier,
// the reported telemetry and (through SharedState) the transports.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/scenario.h"
#include "core/shared_state.h"

namespace swum::emu {

// The ambient temperature a parameter file describes (the paper's bench: room temperature);
// a scenario's `ambient` event shifts the thermal effect by temperature_c - this.
inline constexpr double kReferenceAmbientC = 20.0;

// What holds during one tick.
struct ScenarioConditions {
  std::optional<double> load_n;     // the scenario's load (from its first load event on)
  std::optional<double> ambient_c;  // from the first ambient event on (the parameter file's: kReferenceAmbientC)
  // Motor and amplifier output.
  double phase_a_gain = 1.0, phase_b_gain = 1.0;  // phase_open (0) x voltage_sag (factor)
  double preload_factor = 1.0;
  double guide_friction_factor = 1.0;
  bool jammed = false;
  std::optional<double> jam_position_um;  // absent: where the mover is when the jam starts
  std::uint64_t jam_generation = 0;       // a new jam (even at the same place) has a new number
  bool over_current = false;              // phase_short holds: an enabled amplifier trips
  bool over_temperature = false;
  // Sensors (the reported telemetry only).
  bool encoder_stuck = false;
  double encoder_sigma_um = 0.0;
  bool speed_frozen = false;
  double speed_bias_mm_s = 0.0;
  double speed_sigma_mm_s = 0.0;
  // Communication.
  bool telemetry_silent = false;
  std::uint32_t modbus_drops_started = 0;  // modbus_drop events starting at this tick (their counts, summed)
  double modbus_delay_ms = 0.0;
  bool can_bus_off = false;
  // The scenario's events that took effect at this tick's boundary, for the log ("format_event"
  // text); run-time events are logged by the API that queued them, not by the loop.
  std::vector<const ScenarioEvent*> started;
};

class ScenarioPlayer {
 public:
  ScenarioPlayer(Scenario scenario, double tick_hz);
  // Ticks must be asked for in increasing order (each at most once). Allocation-free after the
  // first call except `started`, which reuses its capacity.
  const ScenarioConditions& at_tick(std::uint64_t tick);
  // A fault (or a clear) given at run time, started at the next at_tick() after the file's
  // events of that tick. False (and counted in `refused`) for a load or ambient event, or with
  // kRuntimeEventCapacity already waiting; a fault that finds kMaxActiveFaults run-time faults
  // in force at that tick is refused and counted then.
  bool queue_runtime(const RuntimeEvent& event);
  // Changes with every change of the faults in force (start, end, clear).
  [[nodiscard]] std::uint64_t generation() const { return generation_; }
  // The faults in force now (after the last at_tick()).
  void active_faults(ActiveFaults& out) const;
  // The load the host commands (where the first load profile starts from); default 0.
  void set_commanded_load_n(double load_n) { commanded_load_n_ = load_n; }
  [[nodiscard]] const Scenario& scenario() const { return scenario_; }
  [[nodiscard]] bool empty() const { return scenario_.events.empty(); }
  // A deterministic standard normal draw (splitmix64 + Box-Muller, seeded by the scenario's
  // seed): the same scenario gives the same noise on every run.
  double normal();

 private:
  struct Active {  // a fault that lasts
    EventType type;
    std::uint64_t start_tick;
    std::uint64_t end_tick;  // 0: until cleared
    EventParameters parameters;
    bool runtime;
  };
  // False when a run-time fault is refused (kMaxActiveFaults run-time faults in force).
  bool start(const ScenarioEvent& e, std::uint64_t tick, bool runtime = false);
  double load_at(std::uint64_t tick) const;
  std::uint64_t to_tick(double seconds) const;

  Scenario scenario_;
  double tick_hz_;
  std::size_t next_ = 0;
  std::vector<Active> active_;
  ScenarioConditions now_;
  // The load profile in force: kind, start, from (value at start), parameters.
  const ScenarioEvent* load_event_ = nullptr;
  std::uint64_t load_start_tick_ = 0;
  double load_from_n_ = 0.0;
  double commanded_load_n_ = 0.0;
  // Run-time events: waiting for the next tick, and the ones started (kept for `started`).
  std::array<ScenarioEvent, kRuntimeEventCapacity> runtime_waiting_;
  std::size_t runtime_waiting_count_ = 0;
  std::array<ScenarioEvent, kRuntimeEventCapacity> runtime_started_;
  std::size_t runtime_active_ = 0;  // run-time faults in active_
  std::uint64_t generation_ = 0;
  std::uint64_t refused_ = 0;
  std::uint64_t rng_state_;
  std::optional<double> spare_normal_;
};

}  // namespace swum::emu
