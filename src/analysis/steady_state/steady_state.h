// Steady-state operating point of the motor: start at the static preload equilibrium, settle,
// then average over windows until two consecutive windows agree (model_spec §10: tau ~ 5-10 ms).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "model/machine/electrical.h"
#include "model/motor_model.h"
#include "model/simulation/window_statistics.h"

namespace swum {

struct OperatingPoint {
  double amplitude_v = 0.0;  // as DriveInput::amplitude_v: terminal amplitude of each phase (V)
  double frequency_hz = 40000.0;
  double load_n = 0.0;
  double phase_deg = 90.0;
  // Slow states of the thermal and wear effects at the start of the run (ignored when the
  // effect is disabled). They evolve during the run (swum simulate, sweeps), unless
  // freeze_slow_states holds them fixed: the quasi-static map of a measured point whose
  // history the caller has already integrated (docs/discrepancy.md).
  double stator_temperature_rise_k = 0.0;
  double sliding_distance_m = 0.0;
  bool freeze_slow_states = false;
  // Start here instead of at rest: the state a previous point of the same sweep left (its
  // SteadyStateResult::final_state). The drive changes phase-continuously, as on a real
  // amplifier that retunes its oscillator; the slow states above replace the snapshot's.
  std::optional<MotorState> initial_state = std::nullopt;
};

// One trace sample (the CLI writes these to CSV; src does no I/O).
struct TraceSample {
  double time_s = 0.0;
  double q1_m = 0.0, q1_dot_m_s = 0.0, q2_m = 0.0, q2_dot_m_s = 0.0;
  double tip_normal_um = 0.0, tip_tangential_um = 0.0;
  double normal_force_n = 0.0, friction_force_n = 0.0;
  double mover_position_m = 0.0, mover_velocity_m_s = 0.0;
};

struct SteadyStateOptions {
  double settle_s = 0.030;  // discarded transient (speed settles with tau ~ 5-10 ms)
  double window_s = 0.010;  // averaging window
  double max_s = 0.100;     // give up (ok = false, values of the last window) after this
  // Two consecutive windows agree when |speed_k - speed_k-1| <= max(abs, rel |speed_k|).
  double speed_tolerance_mm_s = 0.5;
  double speed_relative_tolerance = 0.005;
  // false: run windows until max_s even after two agree (timing runs, slow transients); the
  // result is the last window, ok when its speed agrees with the one before.
  bool stop_when_settled = true;
  // Trace: called every trace_every_steps steps (fixed step) or accepted steps (reference).
  std::uint64_t trace_every_steps = 0;  // 0 = no trace
  std::function<void(const TraceSample&)> trace;
  // Reference solver (run_to_steady_state_reference) only.
  double reference_relative_tolerance = 1e-9;
  double reference_samples_per_cycle = 100.0;  // max step = 1/(this * f): peak sampling
};

struct SteadyStateResult {
  bool ok = false;                     // settled and did not diverge
  bool diverged = false;               // NaN guard tripped (values meaningless)
  std::string failure;                 // why not ok
  double speed_mm_s = 0.0;             // mean mover speed over the last window (dx_m / T)
  double tip_normal_um = 0.0;          // (max - min)/2 of u_tip = -q1 over the last window
  double tip_tangential_um = 0.0;      // (max - min)/2 of w_tip = gTv q2
  double contact_fraction = 0.0;       // fraction of time with F_N > 0
  double mean_friction_force_n = 0.0;  // mean F_T on the mover
  double mean_normal_force_n = 0.0;    // mean F_N
  double friction_force_std_n = 0.0;   // standard deviation of F_T over the window
  double damping_power_w = 0.0;        // mean C1 q1'^2 + C2 q2'^2 (heats the stator)
  // The interface's share of the power balance (window_statistics.h): mean F_T (gT q2' - v_m),
  // the slip in the contact, and mean F_T v_m, what the mover receives (load x speed, mover
  // damping, guide friction). Electrical real power = damping + slip + mover power (tested).
  double slip_power_w = 0.0;
  double mover_power_w = 0.0;
  // The electrical port over the last window (electrical.h; the emulator's definitions and
  // sampling: every MotorSimulator::kElectricalStride-th step at its midpoint). Invalid (all 0)
  // at zero amplitude, from the reference solver, and when the last window ran without
  // statistics (stop_when_settled false: the last window always has them).
  ElectricalReadings electrical;
  double speed_change_mm_s = 0.0;  // speed difference of the last two windows
  double sim_s = 0.0;              // simulated time in total
  std::uint64_t steps = 0;         // solver steps in total (accepted steps for the reference)
  int windows = 0;
  MotorState final_state;  // where the run ended (fixed-step solver only): the next point of a sweep starts here
};

// Options of a run of at most duration_s (swum simulate --duration-s): the default settle and
// window, shrunk so that at least two windows fit, and the default agreement criterion. The run
// stops as soon as two consecutive windows agree; it takes duration_s only if they never do.
[[nodiscard]] SteadyStateOptions steady_state_options_within(double duration_s);

// Fixed-step semi-implicit solver (the HIL scheme, model.time_step_s()).
[[nodiscard]] SteadyStateResult run_to_steady_state(const MotorModel& model, const OperatingPoint& point,
                                                    const SteadyStateOptions& options = {});

// Same procedure with the adaptive Dormand-Prince reference on the full erf model
// (kappa = 3.6 * 10^a). Slow in stick-dominated regimes; meant for accuracy checks.
[[nodiscard]] SteadyStateResult run_to_steady_state_reference(const MotorModel& model, const OperatingPoint& point,
                                                              const SteadyStateOptions& options = {});

// The window rules, shared by run_to_steady_state and the batch runner (steady_state_batch.h).
// store_window: a window's sums (duration_s = the sum of its steps) into r's values.
void store_window(const WindowStatistics& sums, double duration_s, double start_position_m, double end_position_m,
                  SteadyStateResult& r);
// After window r.windows ending at elapsed_s (settle included): true when the run stops, with
// r.ok (the last two windows agree) or r.failure set; otherwise previous_speed_mm_s = this one's.
[[nodiscard]] bool window_verdict(const SteadyStateOptions& options, double elapsed_s, double& previous_speed_mm_s,
                                  SteadyStateResult& r);
[[nodiscard]] std::string diverged_failure(double time_s);
// A window's electrical readings for this point (none at zero amplitude, as the emulator).
[[nodiscard]] ElectricalReadings window_electrical(const ElectricalSums& sums, const OperatingPoint& point);

}  // namespace swum
