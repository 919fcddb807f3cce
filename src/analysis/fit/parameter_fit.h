// Fit of free parameters (free_parameter.h) to measured points: the discrepancy workflow fits a
// new candidate effect jointly with the effects named before it (docs/discrepancy.md), `swum
// calibrate` base parameters of the model (docs/calibration.md);
// bounded Levenberg-Marquardt (Ceres, as identification.cpp) on the relative residuals of the
// training points, forward-difference Jacobian evaluated in the same parallel batch as the
// residuals, cluster-robust sandwich standard errors (fit_parameters).
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "analysis/fit/disagreement_map.h"
#include "analysis/fit/free_parameter.h"
#include "analysis/measurements/measured_point_model.h"

namespace swum {

// Evaluates the model with the free parameters at each of `value_sets` (everything else as the
// current model): one batch.
class ParameterEvaluator {
 public:
  ParameterEvaluator(const MotorParameters& current, std::vector<FreeParameter> free, const MeasurementSet& set,
                     const PredictionOptions& options, const ParallelFor& parallel, int& evaluation_counter);
  [[nodiscard]] std::vector<Predictions> evaluate(const std::vector<std::vector<double>>& value_sets) const;
  [[nodiscard]] MotorParameters parameters_at(std::span<const double> values) const;
  [[nodiscard]] const std::vector<FreeParameter>& free() const { return free_; }

 private:
  MotorParameters current_;
  std::vector<FreeParameter> free_;
  const MeasurementSet* set_;
  PredictionOptions options_;
  ParallelFor parallel_;
  int* counter_;
};

struct ParameterFit {
  bool ok = false;
  std::vector<double> values;  // per free parameter of the evaluator
  std::vector<double> standard_errors;
  std::vector<std::vector<double>> covariance;  // of the values (empty when the bread is singular)
  double train_sum_of_squares = 0.0;
  Predictions predictions;  // all points at `value`
  int iterations = 0;
};

// Starts at `start` (whose predictions may be passed in to save one evaluation); bounds of
// the free parameters; at most `max_iterations` LM iterations. robust_scale > 0: Cauchy loss
// rho(s) = a^2 ln(1 + s/a^2) with a = robust_scale (Ceres' CauchyLoss), an M-estimator that
// heavy-tailed residuals (a reading at the dead-zone edge or across the fold) cannot drag;
// 0: least squares. Standard errors: the cluster-robust sandwich over operating points (the
// quantities and repeats of one point are one cluster; weights w = 1/(1 + r^2/a^2) for the
// M-estimate, 1 for least squares). conservative_errors: each variance is the larger of the
// sandwich's and Huber's classical sum psi^2 / (n - k) / mean(psi') x B^-1 (s^2 (J'J)^-1 for
// least squares): with a few clusters the
// sandwich is biased low (swum calibrate on small sweeps; the discrepancy workflow keeps the
// sandwich alone).
[[nodiscard]] ParameterFit fit_parameters(const ParameterEvaluator& evaluator, const ResidualModel& residuals,
                                          std::span<const std::size_t> train_slots, std::vector<double> start,
                                          int max_iterations, const Predictions* start_predictions = nullptr,
                                          double robust_scale = 0.0, bool conservative_errors = false);

// Cauchy scale for 95 % efficiency at Gaussian residuals of standard deviation sigma.
inline constexpr double kCauchyEfficiencyScale = 2.385;

// Robust standard deviation of the residuals at `slots`: 1.4826 x median |r| (consistent for
// zero-mean Gaussian residuals; structure and a few wild readings do not inflate it much).
[[nodiscard]] double robust_sigma(std::span<const double> r, std::span<const std::size_t> slots);

}  // namespace swum
