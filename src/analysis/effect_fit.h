// Fit of candidate effects' free parameters to measured points (docs/discrepancy.md): the new
// candidate jointly with the effects named before it, so an earlier fit that absorbed part of
// the new effect is corrected;
// bounded Levenberg-Marquardt (Ceres, as identification.cpp) on the relative residuals of the
// training points, forward-difference Jacobian evaluated in the same parallel batch as the
// residuals, standard error from the Gauss-Newton covariance s^2 (J^T J)^-1.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "analysis/candidate_effects.h"
#include "analysis/disagreement_map.h"
#include "analysis/measured_point_model.h"

namespace swum {

// Evaluates the model with the effects' free parameters at each of `value_sets` (the effects
// enabled, everything else as the current model): one batch.
class EffectEvaluator {
 public:
  EffectEvaluator(const MotorParameters& current, std::vector<const CandidateEffect*> effects,
                  const MeasurementSet& set, const PredictionOptions& options,
                  const ParallelFor& parallel, int& evaluation_counter);
  [[nodiscard]] std::vector<Predictions> evaluate(
      const std::vector<std::vector<double>>& value_sets) const;
  [[nodiscard]] MotorParameters parameters_at(std::span<const double> values) const;
  [[nodiscard]] const std::vector<const CandidateEffect*>& effects() const { return effects_; }

 private:
  MotorParameters current_;
  std::vector<const CandidateEffect*> effects_;
  const MeasurementSet* set_;
  PredictionOptions options_;
  ParallelFor parallel_;
  int* counter_;
};

struct EffectFit {
  bool ok = false;
  std::vector<double> values;           // per effect of the evaluator
  std::vector<double> standard_errors;
  double train_sum_of_squares = 0.0;
  Predictions predictions;  // all points at `value`
  int iterations = 0;
};

// Starts at `start` (whose predictions may be passed in to save one evaluation); bounds of
// the candidate; at most `max_iterations` LM iterations.
[[nodiscard]] EffectFit fit_effect(const EffectEvaluator& evaluator,
                                   const ResidualModel& residuals,
                                   std::span<const std::size_t> train_slots,
                                   std::vector<double> start, int max_iterations,
                                   const Predictions* start_predictions = nullptr);

}  // namespace swum
