// N independent operating points of one motor model advanced together (issue 16): the fixed
// step of MotorSimulator (semi-implicit Euler with implicit friction, model_spec §10) on a
// structure of arrays, one SIMD lane per point (Google Highway, runtime dispatch: SSE2 on any
// x86-64, AVX2 / AVX-512 where the CPU has them). Every lane runs the same instructions: the
// contact clamp, separation, the Jenkins return mapping and guide friction are Min/Max and
// masked selects, never a branch that differs per lane. The lane count is padded up to
// kLanePadding with idle lanes (rest state, no drive), so a lane's result depends neither on
// its position nor on the batch size. Against MotorSimulator the lanes agree to rounding (the
// vector targets contract multiply-adds differently), not to the bit.
//
// Supported: rigid Coulomb projection or Jenkins contact, implicit Coulomb or tanh-smoothed
// guide friction (not the exact sign of a zero smoothing width); the time-domain effects
// (effects.h): thermal and wear with their slow states held fixed per lane (as
// MotorSimulator::set_slow_states(..., frozen = true)), the amplifier droop's gain updated per
// lane every 64 steps as MotorSimulator does (scalar code between vector blocks). supports() says
// whether a model is in that set; callers fall back to MotorSimulator otherwise
// (steady_state_batch.h does, also for slow states that must evolve).
//
// Allocation happens in the constructor only; advance() allocates nothing and throws nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "model/machine/electrical.h"
#include "model/machine/motor.h"
#include "model/motor_model.h"
#include "model/simulation/window_statistics.h"

namespace swum {

class BatchSimulator {
 public:
  // Lanes are padded up to a multiple of this (the widest double vector Highway dispatches to
  // on x86-64, AVX-512: 8 lanes).
  static constexpr std::size_t kLanePadding = 8;

  // Whether the lanes implement this model's step (see above).
  [[nodiscard]] static bool supports(const MotorModel& model);

  // The instruction set the lanes run on (Highway's name: "AVX3" = AVX-512, "AVX2", "SSE4", ...).
  [[nodiscard]] static const char* simd_target();
  // The targets compiled in that this CPU runs, best first.
  [[nodiscard]] static std::vector<std::string> available_simd_targets();
  // For tests and benchmarks: run the lanes on `name` (one of available_simd_targets()), or on
  // the best target again (empty name). False for a name not available. Process-wide; not while
  // a batch is advancing on another thread.
  static bool restrict_simd_target(const std::string& name);

  // `lanes` >= 1 lanes, each at rest with no drive. Throws std::invalid_argument if
  // !supports(model). The model must outlive the simulator.
  BatchSimulator(const MotorModel& model, std::size_t lanes);
  ~BatchSimulator();
  BatchSimulator(const BatchSimulator&) = delete;
  BatchSimulator& operator=(const BatchSimulator&) = delete;

  [[nodiscard]] std::size_t lanes() const { return lanes_; }
  [[nodiscard]] const MotorModel& model() const { return model_; }
  [[nodiscard]] double time_step_s() const { return dt_; }

  // Loads a lane as MotorSimulator::set_drive, set_state and set_slow_states(state's
  // temperature rise and sliding distance, frozen = true) would (phasor renormalised, deflection
  // 0 with a rigid contact, slow states 0 for a disabled effect), clears its divergence flag
  // and its window sums.
  void set_lane(std::size_t lane, const MotorState& state, const DriveInput& drive);
  // Rest state at zero drive (an idle lane); idle lanes of a whole vector are not stepped.
  void set_idle(std::size_t lane);
  [[nodiscard]] bool idle(std::size_t lane) const;

  // `steps` steps of every lane that is not idle. The housekeeping of MotorSimulator (phasor
  // renormalisation, subnormal flush) runs every 64 steps of the batch clock: a lane loaded
  // when steps_run() is a multiple of 64 steps exactly as a fresh MotorSimulator does.
  void advance(std::uint64_t steps);
  [[nodiscard]] std::uint64_t steps_run() const { return clock_steps_; }

  [[nodiscard]] MotorState lane_state(std::size_t lane) const;
  // Interface forces of the lane's last step (as MotorSimulator::forces()).
  [[nodiscard]] InterfaceForces lane_forces(std::size_t lane) const;

  // NaN/runaway guard per lane, as MotorSimulator's: the lane is reset to rest, flagged and
  // counted; the other lanes are untouched.
  [[nodiscard]] bool lane_diverged(std::size_t lane) const;
  [[nodiscard]] std::uint64_t lane_divergence_count(std::size_t lane) const;

  void reset_window(std::size_t lane);
  // Per-lane statistics gathered at every step since the lane's last reset_window() (the sums of
  // a steady-state window, window_statistics.h, with the interface's slip and mover energies;
  // duration_s and the damping coefficients are not set: the caller knows the window's length).
  [[nodiscard]] WindowStatistics window(std::size_t lane) const;

  // The electrical port per lane (MotorSimulator::advance(steps, ElectricalSums&)'s samples:
  // every kElectricalStride-th step of the batch clock, at the step's midpoint). A lane samples
  // while set_lane_sampling(lane, true) (set_lane and set_idle turn it off: the settle of a
  // steady state costs nothing); other lanes of its vector group may then gather samples too,
  // which reset_window clears. lane_electrical: the sums since the lane's last reset_window().
  void set_lane_sampling(std::size_t lane, bool on);
  [[nodiscard]] ElectricalSums lane_electrical(std::size_t lane) const;

  // The SoA storage (defined in the .cpp; public for the per-target kernels there).
  struct Arrays;

 private:
  void update_droop();

  const MotorModel& model_;
  std::size_t lanes_;
  std::size_t padded_;
  double dt_;
  std::uint64_t clock_steps_ = 0;
  std::unique_ptr<Arrays> a_;
};

}  // namespace swum
