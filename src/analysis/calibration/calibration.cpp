#include "analysis/calibration/calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>

#include "analysis/calibration/calibration_candidates.h"
#include "analysis/calibration/calibration_detail.h"
#include "analysis/fit/parameter_fit.h"
#include "formats/number_format.h"

namespace swum {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kStep = 0.1;  // finite-difference step in spreads, as parameter_fit.cpp

}  // namespace

CalibrationResult calibrate_to_measurements(const MotorParameters& prior, const MeasurementSet& set,
                                            const CalibrationOptions& options, const ParallelFor& parallel) {
  if (options.max_free < 1) throw std::invalid_argument("max_free must be >= 1");
  if (options.starts < 1) throw std::invalid_argument("starts must be >= 1");
  CalibrationResult result;
  const ResidualModel model(set, options.floor_fraction);
  result.held_out = held_out_rows(set, options.split, result.held_out_points, result.operating_points);
  std::vector<std::size_t> train, test;
  for (std::size_t k = 0; k < model.slots().size(); ++k) {
    (result.held_out[model.slots()[k].row] ? test : train).push_back(k);
  }

  // The pool: the given free set, or the candidates the selection chooses from.
  const bool choose = options.free.empty();
  const std::vector<FreeParameter> pool = calibration_pool(options, prior);
  if (!choose && pool.size() >= train.size()) {
    throw std::invalid_argument(std::to_string(pool.size()) + " free parameters need more than " +
                                std::to_string(train.size()) + " training values");
  }

  // The prior, and with a selection to make, one forward step of every candidate (one batch).
  const ParameterEvaluator pool_eval(prior, pool, set, options.prediction, parallel, result.model_evaluations);
  std::vector<std::vector<double>> sets{std::vector<double>(pool.size())};
  for (std::size_t k = 0; k < pool.size(); ++k) sets[0][k] = pool[k].origin;
  if (choose) {
    for (std::size_t k = 0; k < pool.size(); ++k) {
      std::vector<double> v = sets[0];
      const double step = kStep * pool[k].scale;
      v[k] += v[k] + step <= pool[k].upper ? step : -step;
      sets.push_back(v);
    }
  }
  const std::vector<Predictions> batch = pool_eval.evaluate(sets);
  result.prior_predictions = batch[0];
  const std::vector<double> r_prior = model.residuals(result.prior_predictions);
  const DisagreementMap map = map_disagreement(set, result.prior_predictions, model);
  result.noise = map.noise;
  result.noise_source = map.noise_source;

  std::vector<FreeParameter> free;
  if (choose) {
    Eigen::MatrixXd j(static_cast<Eigen::Index>(train.size()), static_cast<Eigen::Index>(pool.size()));
    const double sigma = std::max(result.noise, options.min_noise);
    for (std::size_t k = 0; k < pool.size(); ++k) {
      const double dtheta = (sets[k + 1][k] - sets[0][k]) / pool[k].scale;
      for (std::size_t i = 0; i < train.size(); ++i) {
        j(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) =
            (model.residual(train[i], batch[k + 1]) - r_prior[train[i]]) / (dtheta * sigma);
      }
    }
    for (std::size_t k : select_free_set(j, pool, options, result.selection)) free.push_back(pool[k]);
  } else {
    free = pool;
  }

  // Fit, drop what the data cannot determine, refit.
  std::vector<CalibratedParameter> dropped;
  std::vector<double> start;
  for (const FreeParameter& f : free) start.push_back(f.origin);
  std::optional<ParameterFit> fit;
  std::mt19937_64 rng(options.seed);
  while (!free.empty()) {
    ++result.rounds;
    const ParameterEvaluator eval(prior, free, set, options.prediction, parallel, result.model_evaluations);
    const std::vector<std::vector<double>> starts = fit_starts(start, free, result.rounds == 1 ? options.starts : 1,
                                                               rng);
    std::optional<ParameterFit> best;
    for (const std::vector<double>& s : starts) {
      const bool at_prior = result.rounds == 1 && s == starts[0];
      ParameterFit f = fit_parameters(eval, model, train, s, options.max_iterations,
                                      at_prior ? &result.prior_predictions : nullptr, 0.0, true);
      ++result.starts_run;
      if (!best || (f.ok && !best->ok) || (f.ok == best->ok && f.train_sum_of_squares < best->train_sum_of_squares)) {
        best = std::move(f);
      }
    }
    if (options.robust && best->ok) {
      const double a = kCauchyEfficiencyScale * robust_sigma(model.residuals(best->predictions), train);
      if (a > 0.0) {
        ParameterFit robust = fit_parameters(eval, model, train, best->values, options.max_iterations,
                                             &best->predictions, a, true);
        if (robust.ok) best = std::move(robust);
      }
    }
    const Undetermined worst = least_determined(best->values, best->standard_errors, free, options);
    if (!best->ok || !worst.index) {
      fit = std::move(best);
      break;
    }
    start = best->values;
    dropped.push_back(hold_at_prior(worst, free, start));
  }

  result.fitted = prior;
  if (fit) {
    for (std::size_t k = 0; k < free.size(); ++k) {
      const FreeParameter& f = free[k];
      free[k].apply(result.fitted, fit->values[k]);
      const double v = fit->values[k];
      CalibratedParameter p{
          f.name,
          f.unit,
          f.origin,
          std::abs(f.scale),
          v,
          fit->standard_errors[k],
          f.lower,
          f.upper,
          fit->ok,
          at_bound(f, v),
          fit->ok ? ""
                  : "the fit failed (no usable Ceres solution, or a prediction diverged at it): held at its prior"};
      if (!fit->ok) {
        p.value = f.origin;
        p.standard_error = kInfinity;
        free[k].apply(result.fitted, f.origin);
      }
      result.parameters.push_back(p);
    }
    if (fit->ok && fit->covariance.size() == free.size()) {
      result.correlations.assign(free.size(), std::vector<double>(free.size()));
      for (std::size_t a = 0; a < free.size(); ++a) {
        for (std::size_t b = 0; b < free.size(); ++b) {
          result.correlations[a][b] = fit->covariance[a][b] / std::sqrt(fit->covariance[a][a] * fit->covariance[b][b]);
        }
      }
    }
  }
  for (const CalibratedParameter& p : dropped) result.parameters.push_back(p);

  result.fitted_predictions = fit && fit->ok ? fit->predictions : result.prior_predictions;
  score_on_measurements(set, model, train, test, options, result);

  int identified = 0;
  for (const CalibratedParameter& p : result.parameters) identified += p.identifiable ? 1 : 0;
  result.conclusion = std::to_string(identified) + " of " + std::to_string(result.parameters.size()) +
                      " free parameters identified" +
                      (choose ? " (chosen from " + std::to_string(pool.size()) + " candidates)" : "") +
                      format_numbers("; held-out RMS %.3g %% -> %.3g %%", 100.0 * result.held_out_rms_prior,
                                     100.0 * result.held_out_rms) +
                      format_numbers(" (noise estimate %.3g %%, ", 100.0 * result.noise) + result.noise_source + ")";
  return result;
}

}  // namespace swum
