// One tick of the emulator without any clock: drain commands, step the amplifier, integrate the
// model over the tick in fixed sub-steps, catch numerical blow-ups, build the telemetry.
// RealtimeLoop calls tick() on its schedule; tests call it directly. No allocation in tick().
#pragma once

#include <array>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <span>
#include <vector>

#include "core/amplifier.h"
#include "core/cia402_drive.h"
#include "core/loop_statistics.h"
#include "core/scenario_player.h"
#include "core/shared_state.h"
#include "model/simulation/model_faults.h"
#include "model/simulation/simulator.h"

namespace swum::emu {

// The model's drive and the loop's statistics as the protocol's telemetry carries them.
inline protocol::DriveValues drive_values(const DriveInput& d) {
  return {d.amplitude_v, d.frequency_hz, d.phase_deg, d.load_n};
}
inline protocol::LoopTiming loop_timing(const LoopStatsSummary& s) {
  return {s.overruns,        s.lateness_p50_ns, s.lateness_p99_ns, s.lateness_p999_ns,
          s.lateness_max_ns, s.compute_p99_ns,  s.compute_max_ns};
}

// Sees what the core applies and publishes, tick by tick (the trace recorder). Called from the
// loop's thread, inside tick().
class TickObserver {
 public:
  virtual ~TickObserver() = default;
  virtual void on_command(std::uint64_t tick, const Command& command) = 0;  // before it is applied at `tick`
  virtual void on_enable_line(std::uint64_t tick, bool enable_line) = 0;    // its value from `tick` on
  virtual void on_telemetry(const Telemetry& telemetry) = 0;                // after each tick
};

struct CoreConfig {
  double tick_hz = 10000.0;
  AmplifierConfig amplifier;  // tick_s is overwritten from tick_hz
  double speed_window_s = 0.010;
  // The phase currents are fitted over windows of this length (whole ticks), one after the
  // other: the telemetry holds the last complete window's values, as a board updates its
  // measurement once per window (and the fit costs once per window, not per tick).
  double electrical_window_s = 0.001;
  unsigned sample_stride = 4;   // sub-steps between tip-amplitude samples
  bool external_clock = false;  // lockstep: reported in the telemetry
  // The CiA 402 drive, run while a CANopen profile's request is active (SharedState::drive_request);
  // its tick rate, amplifier limits and volts conversion are overwritten from the above and the model.
  Cia402DriveConfig drive;
};

class EmulatorCore {
 public:
  EmulatorCore(const MotorModel& model, CoreConfig config, SharedState& shared);

  // Runs one tick; returns the telemetry it published.
  const Telemetry& tick();
  // Drive off (end of run): disable at the next tick boundary, then publish.
  void shut_down();
  // nullptr: none. The observer must outlive the ticks it sees.
  void set_observer(TickObserver* observer) { observer_ = observer; }
  // A scenario's timeline (docs/scenarios.md), applied at every tick boundary from the next tick
  // on. Throws std::invalid_argument when the model cannot play it (an ambient event without the
  // thermal effect). `log`: where each event is reported when it takes effect (nullptr: nowhere).
  void set_scenario(Scenario scenario, std::FILE* log = stderr);

  void set_stats(const LoopStatsSummary& s) { telemetry_.stats = loop_timing(s); }
  [[nodiscard]] const Amplifier& amplifier() const { return amplifier_; }
  [[nodiscard]] const Cia402Drive& drive() const { return drive_; }
  [[nodiscard]] const Telemetry& telemetry() const { return telemetry_; }
  [[nodiscard]] std::uint64_t ticks() const { return tick_; }
  [[nodiscard]] std::uint64_t steps_per_tick() const { return steps_per_tick_; }
  [[nodiscard]] double tick_s() const { return tick_s_; }
  // Tests: replace the model state (e.g. a NaN) to exercise the blow-up path.
  MotorSimulator& simulator() { return simulator_; }
  // Accept times (CLOCK_MONOTONIC ns, stamped by the transports) of the commands applied in
  // the last tick: the first and how many (the loop turns them into latencies).
  [[nodiscard]] std::span<const std::uint64_t> accepted_in_last_tick() const {
    return {accepted_ns_.data(), accepted_count_};
  }

 private:
  const MotorModel& model_;
  CoreConfig config_;
  SharedState& shared_;
  Amplifier amplifier_;
  Cia402Drive drive_;
  MotorSimulator simulator_;
  Telemetry telemetry_;
  double tick_s_;
  std::uint64_t tick_ = 0;
  std::uint64_t steps_done_ = 0;
  std::uint64_t steps_per_tick_ = 0;
  std::vector<double> position_ring_;  // mover position at the end of each of the last N ticks
  std::size_t ring_index_ = 0;
  std::size_t ring_filled_ = 0;
  ElectricalSums electrical_sums_;  // the window under way (electrical.h)
  std::uint64_t electrical_window_ticks_ = 1;
  std::uint64_t electrical_ticks_ = 0;                // ticks in the window under way
  protocol::AmplifierOutputValues amplifier_sums_{};  // the amplifier's readings summed over the window's ticks
  // The terminal voltages' phasors (relative to each phase's source) summed over the window: the
  // parallel inductor's current of the window's mean voltage joins the port's fitted current.
  std::complex<double> terminal_sum_a_{}, terminal_sum_b_{};
  std::array<std::uint64_t, 64> accepted_ns_{};  // first 64 commands of a tick
  std::size_t accepted_count_ = 0;
  TickObserver* observer_ = nullptr;
  // Scenario: the timeline, the model faults in force, what the reported telemetry holds.
  void apply_scenario(const ScenarioConditions& c);
  void report_sensors(const ScenarioConditions& c, double& position_m);
  void report_speed(const ScenarioConditions& c);
  std::optional<ScenarioPlayer> scenario_;
  ActiveFaults active_faults_;  // what was last published (shared_.active_faults)
  std::uint64_t published_faults_generation_ = 0;
  std::FILE* scenario_log_ = nullptr;
  const ScenarioConditions* conditions_ = nullptr;
  ModelFaults faults_;
  std::uint64_t jam_generation_ = 0;
  bool jam_engaged_ = false;            // the mover is against the stop
  std::optional<double> jam_target_m_;  // where the stop is
  double jam_last_position_m_ = 0.0;    // at the last tick boundary, to see the stop reached
  bool encoder_held_ = false, speed_held_ = false;
  double held_position_m_ = 0.0, held_speed_m_s_ = 0.0, held_tick_speed_m_s_ = 0.0;
  int last_enable_line_ = -1;  // what the observer was last told (-1: nothing yet)
};

}  // namespace swum::emu
