// The CiA 402 drive inside the emulator's tick (docs/canopen.md "State machine", "Modes"): each
// tick it reads what the master last wrote (DriveRequest, latched by the CANopen profile), walks
// the power state machine (core/cia402_state.h) and drives the amplifier only through
// Amplifier::apply, so the amplifier's limits, watchdog and fault latch stay the amplifier's.
//  * Profile velocity (3): the velocity demand ramps toward 0x60FF (0x6083 / 0x6084, quick stop
//    0x6085); every control cycle the speed PI (src/controllers/speed_pi.h) sets the amplitude
//    from the demand and the measured speed, the drive phase's sign the direction, and the
//    resonance tracker (src/controllers/resonance_tracker.h, method phase) the frequency: a
//    phase-locked loop on the motional current's phase, phase A forward, phase B reversed.
//  * Open loop (-1): the request's set-points (0x2001-0x2005), clamped to the amplifier's limits.
//  * None (0) or a mode not supported: operation enabled drives 0 V.
// No clock, no allocation, no exception in tick(): everything is sized at construction.
#pragma once

#include <cstdint>

#include "controllers/resonance_tracker.h"
#include "controllers/speed_pi.h"
#include "core/amplifier.h"
#include "core/cia402_state.h"
#include "core/drive_request.h"
#include "model/parameters.h"
#include "telemetry.h"

namespace swum::emu {

using protocol::Telemetry;
class TickObserver;  // core/emulator_core.h

struct Cia402DriveConfig {
  double tick_hz = 10000.0;  // the loop's (EmulatorCore sets it from CoreConfig::tick_hz)
  // The speed loop's and the open loop's cycle: a whole number of ticks (10 at 10 kHz).
  double control_cycle_s = 0.001;
  AmplifierLimits limits;  // the amplifier's (EmulatorCore sets them); every command is kept within
  // Profile velocity: the speed PI (max_amplitude_v is kept within limits.max_amplitude_v). swum
  // control's gains hold with the tracker running too (docs/canopen.md "Modes": the tuning).
  SpeedPiGains speed_gains{kDefaultKpVPerMmS, kDefaultKiVPerMm, 600.0};
  double drive_phase_deg = 90.0;  // phase B - phase A; its sign is the direction
  double frequency_slew_hz_per_s = 1.0e6;
  double amplitude_slew_v_per_s = 1.0e5;
  // The resonance tracker: method phase; its set-point is the request's 0x2031 (the one here
  // is only checked), its frequency range the amplifier's. It steps once every tracker_cycles control cycles (each step
  // reads a fresh electrical window) and only while the amplifier drives at least tracker_min_amplitude_v (no drive, no
  // phase).
  TrackSettings tracker;
  int tracker_cycles = 1;
  double tracker_min_amplitude_v = 10.0;
};

class Cia402Drive {
 public:
  explicit Cia402Drive(const Cia402DriveConfig& config);  // throws std::invalid_argument

  // One tick at its boundary `tick`, after the command queue and the scenario and before the
  // amplifier's tick. `last`: the telemetry published at the end of the previous tick (speed,
  // electrical readings). Does nothing while `request.active` is false (and switches the
  // amplifier off once when it stops being active). `observer` (nullptr: none) sees every
  // command before it is applied, as it sees the queue's (a trace holds all the amplifier's inputs).
  void tick(const DriveRequest& request, Amplifier& amplifier, const Telemetry& last, std::uint64_t tick,
            TickObserver* observer = nullptr);

  // The published values; `output` (the amplifier's drive of this tick) gives 0x2011.
  [[nodiscard]] protocol::Cia402Values values(const DriveInput& output) const;
  [[nodiscard]] Cia402State state() const { return state_; }
  [[nodiscard]] const Cia402DriveConfig& config() const { return config_; }
  [[nodiscard]] std::uint64_t control_cycle_ticks() const { return cycle_ticks_; }
  // The amplifier commands the drive issued and those the amplifier refused (none expected:
  // every set-point is clamped to the limits; an enable while the enable line is low is one).
  [[nodiscard]] std::uint64_t commands_issued() const { return commands_issued_; }
  [[nodiscard]] std::uint64_t commands_refused() const { return commands_refused_; }
  [[nodiscard]] const ResonanceTracker& tracker() const { return tracker_; }

 private:
  Reason apply(Amplifier& amplifier, Command command, std::uint64_t tick);
  void enter(Cia402State next, Amplifier& amplifier, const Telemetry& last, std::uint64_t tick);
  void control_cycle(const DriveRequest& request, Amplifier& amplifier, const Telemetry& last, std::uint64_t tick);
  void profile_velocity_cycle(const DriveRequest& request, Amplifier& amplifier, const Telemetry& last,
                              std::uint64_t tick);
  void open_loop_cycle(const DriveRequest& request, Amplifier& amplifier, std::uint64_t tick);
  void restart_loops(const Telemetry& last);
  void start_tracker(double start_hz, double setpoint_deg);
  void update_flags(const DriveRequest& request, const Amplifier& amplifier, const Telemetry& last);

  Cia402DriveConfig config_;
  std::uint64_t cycle_ticks_ = 10;
  double cycle_s_ = 0.001;
  bool active_ = false;
  Cia402State state_ = Cia402State::not_ready_to_switch_on;
  std::uint16_t error_code_ = 0;
  std::uint32_t seen_fault_reset_edges_ = 0;
  std::uint32_t seen_comm_loss_events_ = 0;
  bool enable_operation_is_stale_ = false;  // quick stop active entered by a heartbeat loss (0x6007 = 3)
  std::int8_t mode_ = canopen::kModeNone;   // the mode of the last control cycle
  bool mode_started_ = false;               // mode_ has run a cycle since operation was enabled
  std::uint64_t ticks_to_cycle_ = 0;
  // Profile velocity.
  SpeedPi pi_;
  ResonanceTracker tracker_;
  bool tracking_ = false;  // the tracker has started since the demand left 0
  bool tracked_once_ = false;
  TrackMode tracker_mode_ = TrackMode::search;
  int tracker_countdown_ = 0;
  double tracker_setpoint_deg_ = 0.0;
  double velocity_demand_m_s_ = 0.0;
  double direction_ = 1.0;
  double frequency_hz_ = 0.0;
  double amplitude_v_ = 0.0;
  bool quick_stop_finished_ = false;
  std::int8_t mode_display_ = canopen::kModeNone;
  std::uint64_t in_window_ticks_ = 0;
  // Status flags of the last cycle.
  bool internal_limit_ = false;
  bool command_refused_ = false;
  Cia402StatusFlags flags_;
  TickObserver* observer_ = nullptr;  // of the tick under way
  std::uint64_t commands_issued_ = 0;
  std::uint64_t commands_refused_ = 0;
};

}  // namespace swum::emu
