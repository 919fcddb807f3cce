#include "analysis/steady_state/steady_state_batch.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <optional>

#include "model/simulation/batch_simulator.h"

namespace swum {
namespace {

std::uint64_t phase_steps(double duration_s, double dt) {
  return static_cast<std::uint64_t>(std::llround(duration_s / dt));
}

DriveInput drive_of(const OperatingPoint& p) {
  DriveInput drive;
  drive.amplitude_v = p.amplitude_v;
  drive.frequency_hz = p.frequency_hz;
  drive.phase_deg = p.phase_deg;
  drive.load_n = p.load_n;
  return drive;
}

// The scalar path: run_to_steady_state point by point, the state carried along each chain.
std::vector<std::vector<SteadyStateResult>> run_chains_scalar(const MotorModel& model,
                                                              std::span<const OperatingChain> chains,
                                                              const SteadyStateOptions& options,
                                                              const ChainPointDone& point_done) {
  std::vector<std::vector<SteadyStateResult>> results(chains.size());
  for (std::size_t c = 0; c < chains.size(); ++c) {
    std::optional<MotorState> carried;
    for (std::size_t k = 0; k < chains[c].size(); ++k) {
      OperatingPoint point = chains[c][k];
      if (k > 0) point.initial_state = carried;
      results[c].push_back(run_to_steady_state(model, point, options));
      carried = results[c].back().final_state;
      if (point_done) point_done(c, k, results[c].back());
    }
  }
  return results;
}

// What one lane is doing.
struct LaneWork {
  bool busy = false;
  std::size_t chain = 0;
  std::size_t index = 0;
  bool settling = true;
  std::uint64_t steps_left = 0;
  std::uint64_t point_steps = 0;
  double elapsed_s = 0.0;
  double previous_speed_mm_s = std::numeric_limits<double>::quiet_NaN();
  double start_position_m = 0.0;
  SteadyStateResult result;
};

class BatchRunner {
 public:
  BatchRunner(const MotorModel& model, std::span<const OperatingChain> chains, const SteadyStateOptions& options,
              std::size_t lanes, const ChainPointDone& point_done)
      : model_(model),
        chains_(chains),
        options_(options),
        point_done_(point_done),
        sim_(model, lanes),
        work_(lanes),
        results_(chains.size()),
        dt_(model.time_step_s()),
        settle_steps_(phase_steps(options.settle_s, dt_)),
        window_steps_(phase_steps(options.window_s, dt_)) {
    // WindowStats sums dt once per step: the same duration to the last bit.
    for (std::uint64_t k = 0; k < window_steps_; ++k) window_duration_s_ += dt_;
    for (std::size_t c = 0; c < chains.size(); ++c) results_[c].resize(chains[c].size());
  }

  std::vector<std::vector<SteadyStateResult>> run() {
    for (std::size_t lane = 0; lane < work_.size(); ++lane) take_next_chain(lane);
    while (true) {
      std::uint64_t chunk = std::numeric_limits<std::uint64_t>::max();
      for (const LaneWork& w : work_) {
        if (w.busy) chunk = std::min(chunk, w.steps_left);
      }
      if (chunk == std::numeric_limits<std::uint64_t>::max()) break;  // every lane idle: done or drained
      sim_.advance(chunk);
      for (std::size_t lane = 0; lane < work_.size(); ++lane) {
        LaneWork& w = work_[lane];
        if (!w.busy) continue;
        w.steps_left -= chunk;
        w.point_steps += chunk;
        // A phase of zero steps (settle_s = 0) ends at once: loop until the lane has steps to run.
        while (w.busy && w.steps_left == 0) end_phase(lane);
      }
    }
    if (failure_) std::rethrow_exception(failure_);
    return std::move(results_);
  }

 private:
  void take_next_chain(std::size_t lane) {
    while (next_chain_ < chains_.size() && chains_[next_chain_].empty()) ++next_chain_;
    if (next_chain_ == chains_.size()) {
      work_[lane].busy = false;
      sim_.set_idle(lane);
      return;
    }
    const OperatingPoint& first = chains_[next_chain_].front();
    start_point(lane, next_chain_, 0, first.initial_state ? *first.initial_state : model_.rest_state());
    ++next_chain_;
  }

  void start_point(std::size_t lane, std::size_t chain, std::size_t index, MotorState state) {
    LaneWork& w = work_[lane];
    // The point's slow states replace the snapshot's, held fixed (run_to_steady_state with
    // freeze_slow_states; the runner takes only frozen points when thermal or wear is on).
    const OperatingPoint& point = chains_[chain][index];
    state.stator_temperature_rise_k = point.stator_temperature_rise_k;
    state.sliding_distance_m = point.sliding_distance_m;
    w = LaneWork{};
    w.busy = true;
    w.chain = chain;
    w.index = index;
    w.settling = true;
    w.steps_left = settle_steps_;
    w.elapsed_s = options_.settle_s;
    sim_.set_lane(lane, state, drive_of(chains_[chain][index]));
  }

  void end_phase(std::size_t lane) {
    LaneWork& w = work_[lane];
    SteadyStateResult& r = w.result;
    r.steps = w.point_steps;
    r.sim_s = sim_.lane_state(lane).time_s;
    if (sim_.lane_diverged(lane)) {
      r.diverged = true;
      r.ok = false;
      r.failure = diverged_failure(r.sim_s);
      return finish_point(lane);
    }
    const double position = sim_.lane_state(lane).mover_position_m;
    if (!w.settling) {
      w.elapsed_s += options_.window_s;
      store_window(sim_.window(lane), window_duration_s_, w.start_position_m, position, r);
      r.electrical = window_electrical(sim_.lane_electrical(lane), chains_[w.chain][w.index]);
      ++r.windows;
      if (window_verdict(options_, w.elapsed_s, w.previous_speed_mm_s, r)) return finish_point(lane);
    }
    w.settling = false;
    w.start_position_m = position;
    w.steps_left = window_steps_;
    sim_.reset_window(lane);
    sim_.set_lane_sampling(lane, true);  // the windows only, not the settle
  }

  void finish_point(std::size_t lane) {
    LaneWork& w = work_[lane];
    w.result.final_state = sim_.lane_state(lane);
    SteadyStateResult& stored = results_[w.chain][w.index] = std::move(w.result);
    if (point_done_) {
      try {
        point_done_(w.chain, w.index, stored);
      } catch (...) {
        if (!failure_) failure_ = std::current_exception();
      }
    }
    if (failure_) {  // draining: the points under way finish, no new one starts
      w.busy = false;
      sim_.set_idle(lane);
    } else if (w.index + 1 < chains_[w.chain].size()) {
      start_point(lane, w.chain, w.index + 1, stored.final_state);
    } else {
      take_next_chain(lane);
    }
  }

  const MotorModel& model_;
  std::span<const OperatingChain> chains_;
  const SteadyStateOptions& options_;
  const ChainPointDone& point_done_;
  BatchSimulator sim_;
  std::vector<LaneWork> work_;
  std::vector<std::vector<SteadyStateResult>> results_;
  std::size_t next_chain_ = 0;
  double dt_;
  std::uint64_t settle_steps_;
  std::uint64_t window_steps_;
  double window_duration_s_ = 0.0;
  std::exception_ptr failure_;  // the first thing point_done threw
};

}  // namespace

bool batch_steady_state_supported(const MotorModel& model, const SteadyStateOptions& options) {
  const double dt = model.time_step_s();
  return BatchSimulator::supports(model) && !(options.trace && options.trace_every_steps > 0) &&
         phase_steps(options.settle_s, dt) % 64 == 0 && phase_steps(options.window_s, dt) % 64 == 0 &&
         phase_steps(options.window_s, dt) > 0;
}

std::vector<std::vector<SteadyStateResult>> run_chains_to_steady_state(const MotorModel& model,
                                                                       std::span<const OperatingChain> chains,
                                                                       const SteadyStateOptions& options,
                                                                       std::size_t lanes,
                                                                       const ChainPointDone& point_done) {
  // Evolving slow states (thermal, wear) change the model every 64 steps: the scalar path.
  const bool evolving =
      model.coefficients().effects.slow() && std::any_of(chains.begin(), chains.end(), [](const OperatingChain& chain) {
        return std::any_of(chain.begin(), chain.end(), [](const OperatingPoint& p) { return !p.freeze_slow_states; });
      });
  if (!batch_steady_state_supported(model, options) || evolving || chains.empty()) {
    return run_chains_scalar(model, chains, options, point_done);
  }
  lanes = std::clamp<std::size_t>(std::min(lanes, chains.size()), 1, 4096);
  BatchRunner runner(model, chains, options, lanes, point_done);
  return runner.run();
}

std::vector<SteadyStateResult> run_points_to_steady_state(const MotorModel& model,
                                                          std::span<const OperatingPoint> points,
                                                          const SteadyStateOptions& options, std::size_t lanes) {
  std::vector<OperatingChain> chains;
  chains.reserve(points.size());
  for (const OperatingPoint& p : points) chains.push_back({p});
  std::vector<std::vector<SteadyStateResult>> per_chain = run_chains_to_steady_state(model, chains, options, lanes);
  std::vector<SteadyStateResult> results;
  results.reserve(points.size());
  for (auto& r : per_chain) results.push_back(std::move(r.front()));
  return results;
}

}  // namespace swum
