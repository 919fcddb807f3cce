// The model's prediction of measured operating points (docs/discrepancy.md): the steady state
// at each point under a fixed measurement protocol, with the slow states of the thermal and
// wear effects mapped quasi-statically from the session history (points ordered by time_s; the
// motor runs at point i from time_s[i] until time_s[i+1]; the session starts cold and unworn).
// The history needs each point's damping power and speed, which depend on the slow states:
// `history_passes` fixed-point passes (pass 1 at zero slow states; all but the last with the
// shorter history protocol). The same procedure is the
// model for synthetic data and for the fits, so both agree exactly.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "analysis/measurements/measurements.h"
#include "analysis/steady_state/parallel_for.h"
#include "analysis/steady_state/steady_state.h"
#include "model/parameters.h"

namespace swum {

struct PredictionOptions {
  // Measurement protocol: from rest, settle 40 ms, average one 10 ms window (fixed length, so
  // the prediction is a smooth function of the parameters for finite differences).
  SteadyStateOptions steady = measurement_protocol();
  int history_passes = 3;  // temperature error shrinks ~4x per pass (docs/discrepancy.md)
  // The passes before the last only feed power and speed into the history: a shorter run.
  SteadyStateOptions history = history_protocol();

  [[nodiscard]] static SteadyStateOptions measurement_protocol() {
    SteadyStateOptions o;
    o.settle_s = 0.040;
    o.window_s = 0.010;
    o.max_s = 0.050;
    return o;
  }
  [[nodiscard]] static SteadyStateOptions history_protocol() {
    SteadyStateOptions o;
    o.settle_s = 0.020;
    o.window_s = 0.005;
    o.max_s = 0.025;
    return o;
  }
};

struct PredictedPoint {
  bool ok = false;                              // false: the simulation diverged (values meaningless)
  std::array<double, kQuantityCount> values{};  // speed_mm_s, tip_normal_um, tip_tangential_um
  double damping_power_w = 0.0;
  double stator_temperature_rise_k = 0.0;  // slow states used at this point
  double sliding_distance_m = 0.0;

  [[nodiscard]] double value(Quantity q) const { return values[static_cast<std::size_t>(q)]; }
};

using Predictions = std::vector<PredictedPoint>;

// Called as soon as a point's prediction for a model is final (its last pass), from the tasks
// of `parallel`: concurrently, in no particular order. `swum synth` writes rows as they come.
using PointPredicted = std::function<void(std::size_t model, std::size_t point, const PredictedPoint& p)>;

// Predictions of every point for each parameter set (one batch keeps both cores busy).
[[nodiscard]] std::vector<Predictions> predict_points(std::span<const MotorParameters> models,
                                                      std::span<const Measurement> points,
                                                      const PredictionOptions& options, const ParallelFor& parallel,
                                                      const PointPredicted& point_predicted = {});

// The runs a prediction makes, in session order: each sweep (rows sharing a `sweep` id) is one
// chain whose points start from the state the previous point left; every other row is a chain
// of its own, from rest (docs/discrepancy.md, "What a prediction of a measured point is").
[[nodiscard]] std::vector<std::vector<std::size_t>> prediction_chains(std::span<const Measurement> points);

// Points in session order (stable sort by time_s; rows without time keep file order).
[[nodiscard]] std::vector<std::size_t> session_order(std::span<const Measurement> points);

}  // namespace swum
