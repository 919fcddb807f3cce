// Fixed-step simulation of one motor (the HIL core): semi-implicit Euler with implicit
// friction (model_spec §10), drive phasor, NaN/runaway guard. No allocation, no virtual call,
// no I/O and no throw in step()/advance().
#pragma once

#include <cstdint>

#include "model/machine/drive.h"
#include "model/machine/drive_recurrence.h"
#include "model/machine/electrical.h"
#include "model/machine/motor.h"
#include "model/machine/output_network.h"
#include "model/motor_model.h"
#include "model/simulation/model_faults.h"
#include "model/simulation/window_statistics.h"

namespace swum {

// Observable outputs after a step.
struct MotorOutputs {
  double time_s = 0.0;
  double tip_normal_um = 0.0;      // u_tip = -q1
  double tip_tangential_um = 0.0;  // w_tip = gTv q2
  double normal_force_n = 0.0;     // F_N
  double friction_force_n = 0.0;   // F_T on the mover
  double guide_force_n = 0.0;      // F_f
  double mover_position_m = 0.0;
  double mover_velocity_m_s = 0.0;
};

class MotorSimulator {
 public:
  // Starts at model.rest_state() with a zero drive. The model must outlive the simulator.
  explicit MotorSimulator(const MotorModel& model);

  MotorSimulator(const MotorSimulator&) = delete;
  MotorSimulator& operator=(const MotorSimulator&) = delete;

  // New drive for the following steps. The drive phase theta stays continuous; only the
  // amplitude, frequency, phase difference and load change. Cheap when only the voltage or
  // the load changes (the rotation is recomputed only for a new frequency or phase).
  void set_drive(const DriveInput& input);
  [[nodiscard]] const DriveInput& drive() const { return drive_; }

  // One step of model.time_step_s().
  void step();
  // `steps` steps (the hot loop).
  void advance(std::uint64_t steps);
  // The same steps, adding each step's end state and interface forces to `window` (the
  // steady-state windows): the same trajectory and the same sums as step() in a loop followed
  // by window.add(...) from state() and forces(), at the cost of the hot loop.
  void advance(std::uint64_t steps, WindowStatistics& window);
  // The same steps, adding the phase currents and voltages of every kElectricalStride-th step
  // (at the step's midpoint) to `sums` (electrical.h: the amplifier's measurement of its
  // outputs). Same trajectory as advance(steps).
  static constexpr std::uint64_t kElectricalStride = 4;
  void advance(std::uint64_t steps, ElectricalSums& sums);
  // Both at once (the steady-state windows with the electrical port).
  void advance(std::uint64_t steps, WindowStatistics& window, ElectricalSums& sums);

  [[nodiscard]] const MotorState& state() const { return state_; }
  // Replaces the state (e.g. a snapshot); the phasor is renormalised.
  void set_state(const MotorState& state);
  // Rest state (static preload equilibrium) at the current time; drive kept.
  void reset();

  [[nodiscard]] const InterfaceForces& forces() const { return system_.forces(); }
  [[nodiscard]] MotorOutputs outputs() const;
  [[nodiscard]] DriveVoltages voltages() const { return drive_voltages(waveform_, state_.drive_sin, state_.drive_cos); }
  [[nodiscard]] double time_step_s() const { return dt_; }
  [[nodiscard]] const MotorModel& model() const { return model_; }

  // Slow states of the thermal and wear effects (no-ops when both are disabled). Frozen slow
  // states keep their values (the quasi-static map of a measured point, steady_state.h);
  // otherwise they evolve every housekeeping block (64 steps).
  void set_slow_states(double temperature_rise_k, double sliding_distance_m, bool frozen);
  [[nodiscard]] bool slow_states_frozen() const { return slow_states_frozen_; }
  // Ambient temperature of the thermal effect relative to the one the parameter file describes
  // (K; the emulator's scenario `ambient` event): the stiffness and damping factors see
  // offset + rise, the rise itself (driven by the losses) is unchanged. No-op without the effect.
  void set_ambient_offset_k(double offset_k);
  [[nodiscard]] double ambient_offset_k() const { return ambient_offset_k_; }
  // Drive amplitude at the piezo / commanded (amplifier droop; 1 when disabled or when the
  // [amplifier] network carries the droop's source resistance).
  [[nodiscard]] double droop_gain() const { return droop_gain_; }
  // The [amplifier] output network (output_network.h; docs/amplifier.md): per phase, terminal
  // voltage / source voltage as a sine phasor, updated every housekeeping block ((1, 0) without a
  // network). The amplifier's current and the terminal voltages, from the state now (the motional
  // current of the modal coordinates' analytic signals, linear coupling) and these gains; with
  // an ideal source (no network) the same with the terminal voltage the commanded one (times
  // the droop gain): C0's current plus the motional one.
  [[nodiscard]] Phasor network_gain_a() const { return network_a_.gain; }
  [[nodiscard]] Phasor network_gain_b() const { return network_b_.gain; }
  // The current here is the LINEAR motional current (a0 q1' + b0 q2'), without the electrical
  // port's non-linear coupling terms (e311, e3111: ElectricalReadings has them), so at high drive
  // its phase is off: -5.9 deg against the port's -0.03 deg at 400 V with the parallel inductor
  // swum size buys (docs/amplifier.md, "The amplifier's readings"). swum-emu's current registers
  // (45-48) therefore no longer come from here but from the port's fit plus the inductor's
  // current; its terminal voltages (49-50) still do. Kept as it is: the network's envelope uses
  // the same linear current.
  [[nodiscard]] AmplifierReadings amplifier_readings() const;
  // Blocks whose network update was refused: the terminal voltage would have been more than
  // kLargestNetworkGain times the source's, or not finite (a network whose fixed point diverges,
  // docs/amplifier.md). The gains are then held. Counted, never thrown.
  static constexpr double kLargestNetworkGain = 1000.0;
  [[nodiscard]] std::uint64_t network_divergence_count() const { return network_divergence_count_; }

  // Run-time motor/amplifier faults (model_faults.h; docs/model.md "Run-time faults"), for the
  // emulator's scenario timeline: call between steps (at tick boundaries), never from inside a
  // step. Throws std::invalid_argument naming the field when check(faults) fails (the faults
  // in force are then unchanged). Takes effect from the current state: the phase amplitudes,
  // F_P and mu_s of the guide change for the following steps; a jam holds the mover at
  // jam_position_m (NaN: where it is now) with v_m = 0 at once, and faults() then reports the
  // position used. set_faults(ModelFaults{}) restores the nominal dynamics, bit-identical to a
  // simulator that never had faults. reset() and set_state() keep the faults (a jammed mover
  // stays at the jam position).
  void set_faults(const ModelFaults& faults);
  [[nodiscard]] const ModelFaults& faults() const { return faults_; }

  // NaN guard (MuJoCo style): a non-finite or runaway state after a step resets to the rest
  // state, sets diverged() and counts a warning.
  [[nodiscard]] bool diverged() const { return diverged_; }
  [[nodiscard]] std::uint64_t divergence_count() const { return divergence_count_; }
  void clear_diverged() { diverged_ = false; }

 private:
  // kJammed: the mover held at faults_.jam_position_m (selected once per advance()).
  // kElectrical: add each step's currents to *sums.
  template <TangentialContact C, GuideFrictionModel G, bool kWindow, bool kJammed, bool kElectrical = false>
  void advance_specialised(std::uint64_t steps, WindowStatistics* window, ElectricalSums* sums = nullptr);
  // The same step fused by hand for the Jenkins contact and the implicit Coulomb guide
  // (simulator_loop.h), the calibrated motor's: every sweep, fit and the emulator.
  template <bool kWindow, bool kElectrical>
  void advance_jenkins(std::uint64_t steps, WindowStatistics* window, ElectricalSums* sums);
  // V_A and V_B amplitudes of waveform_ from its V0 and the phase gains of faults_.
  void apply_phase_gains();
  // Mover at the jam position at rest when jammed.
  void hold_jammed_mover();

  // Housekeeping of the enabled effects (effects.h), every 64 steps.
  void update_effects(const MotorSplitSystem::Vector& q, const MotorSplitSystem::Vector& v, double sin_theta,
                      double cos_theta, DriveWaveform& waveform);
  void apply_slow_states();
  // The waveform the steps see: waveform_ with the droop gain or the network's phase gains.
  [[nodiscard]] DriveWaveform amplified_waveform() const;
  void update_network(const MotorSplitSystem::Vector& q, const MotorSplitSystem::Vector& v, double sin_theta,
                      double cos_theta, DriveWaveform& waveform);
  // The sine phasors of the two motional currents (A) at the phasor (sin, cos) of the drive.
  void motional_currents(const MotorSplitSystem::Vector& q, const MotorSplitSystem::Vector& v, double sin_theta,
                         double cos_theta, double angular_frequency_rad_s, Phasor& a, Phasor& b) const;

  const MotorModel& model_;
  MotorSplitSystem system_;
  MotorState state_;
  DriveInput drive_{};
  DriveWaveform waveform_{};
  bool waveform_valid_ = false;
  double dt_;
  double position_limit_m_;
  double speed_limit_m_s_;
  std::uint64_t housekeeping_steps_ = 0;  // phasor renormalisation / subnormal flush cadence
  bool slow_states_frozen_ = false;
  double ambient_offset_k_ = 0.0;
  double droop_gain_ = 1.0;
  NetworkPhase network_a_{};
  NetworkPhase network_b_{};
  std::uint64_t network_divergence_count_ = 0;
  ModelFaults faults_{};
  bool diverged_ = false;
  std::uint64_t divergence_count_ = 0;
  // (sin, cos) at mid-step = (phasor at t_n + phasor at t_n+1) x this = 1 / (2 cos(w dt/2)):
  // the electrical port's sampling point, computed once per drive frequency (set_drive).
  double midpoint_scale_ = 0.5;
  // The drive phasor and modal-cubic coefficients of advance_jenkins between calls, so that
  // advance(n) and n calls of step() give the same bits. Anchored at every 64-step boundary (the
  // renormalised phasor); a new frequency, phase or state anchors it where it happens
  // (unanchored); new amplitudes (drive, phase faults, droop) or a new modal stiffness (thermal)
  // are replayed from the anchor (stale), so that the values at a step do not depend on when
  // such a change was made.
  enum class RecurrenceState { current, stale, unanchored };
  struct RecurrenceAnchor {
    double sin_theta = 0.0, cos_theta = 1.0;
    std::uint64_t step = 0;  // housekeeping_steps_ at the anchor
  };
  DriveRecurrence drive_recurrence_{};
  RecurrenceState drive_recurrence_state_ = RecurrenceState::unanchored;
  RecurrenceAnchor recurrence_anchor_{};
  // Marks the recurrence stale unless it is already unanchored.
  void recurrence_inputs_changed() {
    if (drive_recurrence_state_ == RecurrenceState::current) drive_recurrence_state_ = RecurrenceState::stale;
  }
  bool fused_step_ = true;  // numerics.step_kernel
};

}  // namespace swum
