#include "analysis/measurements/measured_point_model.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numeric>
#include <optional>

#include "analysis/steady_state/steady_state_batch.h"
#include "model/motor_model.h"
#include "model/simulation/batch_simulator.h"

namespace swum {
namespace {

struct SlowState {
  double temperature_rise_k = 0.0;
  double sliding_distance_m = 0.0;
};

// Slow states at each point from the previous pass: integrate the session in time order with
// each point's power and speed held until the next point.
std::vector<SlowState> session_history(const EffectCoefficients& e, std::span<const Measurement> points,
                                       std::span<const std::size_t> order, const Predictions& previous) {
  std::vector<SlowState> states(points.size());
  SlowState s;
  double time_s = 0.0;
  const PredictedPoint* running = nullptr;  // nothing runs before the first point
  for (std::size_t i : order) {
    const double t = points[i].time_s.value_or(time_s);
    const double dt = std::max(0.0, t - time_s);
    if (running != nullptr && running->ok) {
      if (e.thermal) s.temperature_rise_k = thermal_step_k(e, s.temperature_rise_k, running->damping_power_w, dt);
      if (e.wear) s.sliding_distance_m += 1e-3 * std::abs(running->value(Quantity::speed)) * dt;
    } else if (e.thermal) {
      s.temperature_rise_k = thermal_step_k(e, s.temperature_rise_k, 0.0, dt);
    }
    time_s = std::max(time_s, t);
    states[i] = s;
    running = &previous[i];
  }
  return states;
}

}  // namespace

std::vector<std::size_t> session_order(std::span<const Measurement> points) {
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return points[a].time_s.value_or(0.0) < points[b].time_s.value_or(0.0);
  });
  return order;
}

std::vector<std::vector<std::size_t>> prediction_chains(std::span<const Measurement> points) {
  std::vector<std::vector<std::size_t>> chains;
  std::map<int, std::size_t> chain_of_sweep;
  for (std::size_t i : session_order(points)) {
    if (!points[i].sweep) {
      chains.push_back({i});
      continue;
    }
    const auto [it, added] = chain_of_sweep.try_emplace(*points[i].sweep, chains.size());
    if (added) chains.emplace_back();
    chains[it->second].push_back(i);
  }
  return chains;
}

std::vector<Predictions> predict_points(std::span<const MotorParameters> parameters,
                                        std::span<const Measurement> points, const PredictionOptions& options,
                                        const ParallelFor& parallel, const PointPredicted& point_predicted) {
  const std::size_t n = points.size();
  std::vector<std::unique_ptr<MotorModel>> models;
  for (const MotorParameters& p : parameters) models.push_back(std::make_unique<MotorModel>(p));
  const bool timed = std::all_of(points.begin(), points.end(),
                                 [](const Measurement& m) { return m.time_s.has_value(); });
  const std::vector<std::size_t> order = session_order(points);
  // Longest chains first, so the last task to start is a short one.
  std::vector<std::vector<std::size_t>> chains = prediction_chains(points);
  std::stable_sort(chains.begin(), chains.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  const std::size_t chain_count = chains.size();
  // Chains per task: one vector of SIMD lanes where every model runs in lanes, else one.
  bool in_lanes = true;
  for (const auto& model : models) {
    in_lanes = in_lanes && batch_steady_state_supported(*model, options.steady) &&
               batch_steady_state_supported(*model, options.history);
  }
  const std::size_t per_group = in_lanes ? BatchSimulator::kLanePadding : 1;
  const std::size_t groups = std::max<std::size_t>(1, (chain_count + per_group - 1) / per_group);
  std::vector<Predictions> out(models.size(), Predictions(n));
  std::vector<std::vector<SlowState>> slow(models.size(), std::vector<SlowState>(n));
  std::vector<int> passes(models.size(), 1);
  for (std::size_t m = 0; m < models.size(); ++m) {
    if (timed && models[m]->coefficients().effects.slow()) passes[m] = std::max(1, options.history_passes);
  }
  const int max_passes = *std::max_element(passes.begin(), passes.end());
  for (int pass = 0; pass < max_passes; ++pass) {
    std::vector<std::size_t> active;
    for (std::size_t m = 0; m < models.size(); ++m) {
      if (pass < passes[m]) active.push_back(m);
    }
    if (pass > 0) {
      for (std::size_t m : active) {
        slow[m] = session_history(models[m]->coefficients().effects, points, order, out[m]);
      }
    }
    // One task per (model, group of chains): a group shares the SIMD lanes of a batch
    // (steady_state_batch.h; where the lanes do not run the model, a group is one chain, run by
    // the scalar path as before). The points of a sweep run one after the other, each from the
    // state the previous one left; a diverged point hands on the rest state.
    parallel(active.size() * groups, [&](std::size_t task) {
      const std::size_t m = active[task / groups];
      const std::size_t g = task % groups;
      const bool final_pass = pass == passes[m] - 1;
      // Chains g, g + groups, ...: longest first, spread evenly over the groups.
      std::vector<const std::vector<std::size_t>*> members;
      std::vector<OperatingChain> group;
      for (std::size_t c = g; c < chain_count; c += groups) {
        members.push_back(&chains[c]);
        OperatingChain& chain = group.emplace_back();
        for (std::size_t i : chains[c]) {
          OperatingPoint point;
          point.amplitude_v = points[i].amplitude_v;
          point.frequency_hz = points[i].frequency_hz;
          point.load_n = points[i].load_n;
          point.stator_temperature_rise_k = slow[m][i].temperature_rise_k;
          point.sliding_distance_m = slow[m][i].sliding_distance_m;
          point.freeze_slow_states = true;  // the session history above sets them
          chain.push_back(point);
        }
      }
      (void)run_chains_to_steady_state(*models[m], group, final_pass ? options.steady : options.history,
                                       BatchSimulator::kLanePadding,
                                       [&](std::size_t c, std::size_t k, const SteadyStateResult& r) {
                                         const std::size_t i = (*members[c])[k];
                                         PredictedPoint& p = out[m][i];
                                         p.ok = !r.diverged;
                                         p.values = {r.speed_mm_s, r.tip_normal_um, r.tip_tangential_um};
                                         p.damping_power_w = r.damping_power_w;
                                         p.stator_temperature_rise_k = group[c][k].stator_temperature_rise_k;
                                         p.sliding_distance_m = group[c][k].sliding_distance_m;
                                         if (final_pass && point_predicted) point_predicted(m, i, p);
                                       });
    });
  }
  return out;
}

}  // namespace swum
