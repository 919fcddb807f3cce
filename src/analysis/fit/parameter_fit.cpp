#include "analysis/fit/parameter_fit.h"

#include <ceres/ceres.h>
#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace swum {

ParameterEvaluator::ParameterEvaluator(const MotorParameters& current, std::vector<FreeParameter> free,
                                       const MeasurementSet& set, const PredictionOptions& options,
                                       const ParallelFor& parallel, int& evaluation_counter)
    : current_(current),
      free_(std::move(free)),
      set_(&set),
      options_(options),
      parallel_(parallel),
      counter_(&evaluation_counter) {}

MotorParameters ParameterEvaluator::parameters_at(std::span<const double> values) const {
  MotorParameters p = current_;
  for (std::size_t k = 0; k < free_.size(); ++k) free_[k].apply(p, values[k]);
  return p;
}

std::vector<Predictions> ParameterEvaluator::evaluate(const std::vector<std::vector<double>>& value_sets) const {
  std::vector<MotorParameters> models;
  for (const auto& v : value_sets) models.push_back(parameters_at(v));
  *counter_ += static_cast<int>(value_sets.size());
  return predict_points(models, set_->rows, options_, parallel_);
}

namespace {

using Theta = std::vector<double>;

// theta_k = (value_k - origin_k) / scale_k: each free parameter in units of its scale. The predictions of every point
// at the parameter sets the solver asks for, computed in one parallel batch per request and cached (Ceres re-evaluates
// accepted points, and every residual block of one evaluation reads the same batch).
class PredictionCache {
 public:
  PredictionCache(const ParameterEvaluator& evaluator, double step, Theta upper_theta)
      : evaluator_(evaluator), step_(step), upper_theta_(std::move(upper_theta)) {}

  [[nodiscard]] std::size_t size() const { return upper_theta_.size(); }

  [[nodiscard]] std::vector<double> values_of(const Theta& theta) const {
    std::vector<double> v(theta.size());
    for (std::size_t k = 0; k < theta.size(); ++k) {
      const FreeParameter& f = evaluator_.free()[k];
      v[k] = f.origin + theta[k] * f.scale;
    }
    return v;
  }

  void remember(const Theta& theta, const Predictions& p) { cache_.emplace(theta, p); }

  // Signed finite-difference step of parameter k that stays inside the bounds.
  [[nodiscard]] Theta shifted(const Theta& theta, std::size_t k) const {
    Theta t = theta;
    t[k] += theta[k] + step_ <= upper_theta_[k] ? step_ : -step_;
    return t;
  }

  // Predictions at theta, and with `jacobian` also at the shifted points (one batch).
  const Predictions& at(const Theta& theta, bool jacobian = false) {
    std::vector<Theta> needed{theta};
    if (jacobian) {
      for (std::size_t k = 0; k < size(); ++k) needed.push_back(shifted(theta, k));
    }
    std::vector<Theta> missing;
    for (const Theta& t : needed) {
      if (cache_.find(t) == cache_.end() && std::find(missing.begin(), missing.end(), t) == missing.end()) {
        missing.push_back(t);
      }
    }
    if (!missing.empty()) {
      std::vector<std::vector<double>> values;
      for (const Theta& t : missing) values.push_back(values_of(t));
      std::vector<Predictions> batch = evaluator_.evaluate(values);
      for (std::size_t k = 0; k < missing.size(); ++k) cache_.emplace(missing[k], std::move(batch[k]));
    }
    return cache_.find(theta)->second;
  }

  // Residual of `slot` at theta and, if asked, its forward-difference gradient (size() values).
  double residual(const ResidualModel& model, std::size_t slot, const Theta& theta, double* gradient) {
    const double r = model.residual(slot, at(theta, gradient != nullptr));
    if (gradient != nullptr) {
      for (std::size_t k = 0; k < size(); ++k) {
        const Theta t = shifted(theta, k);
        gradient[k] = (model.residual(slot, cache_.find(t)->second) - r) / (t[k] - theta[k]);
      }
    }
    return r;
  }

 private:
  const ParameterEvaluator& evaluator_;
  double step_;
  Theta upper_theta_;
  std::map<Theta, Predictions> cache_;
};

// One measured value as a Ceres residual block, so a loss function acts on each residual (a
// loss on one block of all residuals would act on their sum of squares: least squares again).
class SlotResidual final : public ceres::CostFunction {
 public:
  SlotResidual(PredictionCache& cache, const ResidualModel& model, std::size_t slot)
      : cache_(cache), model_(model), slot_(slot) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(cache.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Theta theta(parameters[0], parameters[0] + cache_.size());
    const bool want_jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    residuals[0] = cache_.residual(model_, slot_, theta, want_jacobian ? jacobians[0] : nullptr);
    return std::isfinite(residuals[0]);
  }

 private:
  PredictionCache& cache_;
  const ResidualModel& model_;
  std::size_t slot_;
};

}  // namespace

ParameterFit fit_parameters(const ParameterEvaluator& evaluator, const ResidualModel& residuals,
                            std::span<const std::size_t> train_slots, std::vector<double> start, int max_iterations,
                            const Predictions* start_predictions, double robust_scale, bool conservative_errors) {
  const std::size_t m = evaluator.free().size();
  Theta lo(m), hi(m), theta(m);
  for (std::size_t k = 0; k < m; ++k) {
    const FreeParameter& f = evaluator.free()[k];
    // Bounds in theta units (scale may be negative).
    lo[k] = (f.lower - f.origin) / f.scale;
    hi[k] = (f.upper - f.origin) / f.scale;
    if (lo[k] > hi[k]) std::swap(lo[k], hi[k]);
    theta[k] = std::clamp((start[k] - f.origin) / f.scale, lo[k], hi[k]);
  }
  constexpr double kStep = 0.1;  // 10 % of the scale: far above the steady-state noise
  PredictionCache cache(evaluator, kStep, hi);
  if (start_predictions != nullptr && cache.values_of(theta) == start) cache.remember(theta, *start_predictions);
  ceres::Problem problem;
  for (std::size_t slot : train_slots) {
    problem.AddResidualBlock(new SlotResidual(cache, residuals, slot),
                             robust_scale > 0.0 ? new ceres::CauchyLoss(robust_scale) : nullptr, theta.data());
  }
  for (std::size_t k = 0; k < m; ++k) {
    problem.SetParameterLowerBound(theta.data(), static_cast<int>(k), lo[k]);
    problem.SetParameterUpperBound(theta.data(), static_cast<int>(k), hi[k]);
  }
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = max_iterations;
  so.function_tolerance = 1e-5;
  so.parameter_tolerance = 1e-4;
  so.num_threads = 1;  // the parallelism is inside the cost function
  // No projected line search after each bounded step: each of its probes costs a Jacobian (two
  // model evaluations of every point) and on these steps it bought nothing (47 probes in 8
  // iterations of a 200-point fit). The trust region alone keeps the steps inside the bounds.
  so.max_num_line_search_step_size_iterations = 0;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);

  ParameterFit fit;
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.ok = summary.IsSolutionUsable();
  // Jacobian and residuals at the solution (cached when Ceres evaluated them).
  const std::size_t n = train_slots.size();
  std::vector<double> r(n), j(n * m);
  for (std::size_t i = 0; i < n; ++i) {
    r[i] = cache.residual(residuals, train_slots[i], theta, &j[i * m]);
    fit.ok = fit.ok && std::isfinite(r[i]);
  }
  // Standard errors: the cluster-robust sandwich B^-1 M B^-1, B = sum psi'(r_i) J_i J_i', with
  // the meat summed over operating points, M = G/(G-1) (n-1)/(n-k) sum_g u_g u_g',
  // u_g = sum_{i in g} psi(r_i) J_i, psi(r) = w r:
  // the quantities and repeats of one point share its errors (drive, sensor set-up), so they
  // are one cluster, and the meat needs no assumption about the noise level (w = 1 for least
  // squares, the Cauchy weights 1/(1 + r^2/a^2) for the M-estimate, psi'(r) = (1 - r^2/a^2) w^2).
  const auto mk = static_cast<Eigen::Index>(m);
  Eigen::MatrixXd bread = Eigen::MatrixXd::Zero(mk, mk);
  std::map<std::array<double, 3>, Eigen::VectorXd> scores;
  double weighted_square_sum = 0.0;
  double slope_sum = 0.0;
  const double a2 = robust_scale * robust_scale;
  for (std::size_t i = 0; i < n; ++i) {
    fit.train_sum_of_squares += r[i] * r[i];
    // psi(r) = w r is the M-estimator's score; the bread takes its slope psi'(r) (Huber 1967).
    const double u = robust_scale > 0.0 ? r[i] * r[i] / a2 : 0.0;
    const double w = 1.0 / (1.0 + u);
    const double slope = (1.0 - u) * w * w;
    const Eigen::Map<const Eigen::VectorXd> ji(&j[i * m], mk);
    bread += slope * ji * ji.transpose();
    const Measurement& row = residuals.set().rows[residuals.slots()[train_slots[i]].row];
    auto [it, added] = scores.try_emplace({row.amplitude_v, row.frequency_hz, row.load_n}, Eigen::VectorXd::Zero(mk));
    it->second += w * r[i] * ji;
    weighted_square_sum += w * r[i] * w * r[i];
    slope_sum += slope;
  }
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(mk, mk);
  for (const auto& [key, u] : scores) meat += u * u.transpose();
  const double clusters = static_cast<double>(scores.size());
  const double nd = static_cast<double>(n);
  const double dof = std::max(1.0, nd - static_cast<double>(m));
  if (clusters > 1.0) meat *= clusters / (clusters - 1.0) * (nd - 1.0) / dof;
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(bread);
  Eigen::MatrixXd covariance;
  if (lu.isInvertible()) {
    const Eigen::MatrixXd inverse = lu.inverse();
    covariance = inverse * meat * inverse;
    if (conservative_errors) {
      // Huber's classical covariance: sum psi^2 / (n - k) / mean(psi') x B^-1 (for least squares
      // psi' = 1 and this is s^2 (J'J)^-1).
      const double mean_slope = slope_sum / nd;
      const Eigen::MatrixXd classical = weighted_square_sum / dof / std::max(mean_slope, 1e-12) * inverse;
      for (Eigen::Index k = 0; k < mk; ++k) {
        if (classical(k, k) > covariance(k, k)) {
          // Scale row and column k so the variance is the classical one and the correlations
          // stay the sandwich's.
          const double f = std::sqrt(classical(k, k) / covariance(k, k));
          covariance.row(k) *= f;
          covariance.col(k) *= f;
        }
      }
    }
  }
  fit.values = cache.values_of(theta);
  for (std::size_t k = 0; k < m; ++k) {
    const auto ik = static_cast<Eigen::Index>(k);
    const double var = covariance.size() > 0 ? covariance(ik, ik) : -1.0;
    fit.standard_errors.push_back(var > 0.0 ? std::sqrt(var) * std::abs(evaluator.free()[k].scale)
                                            : std::numeric_limits<double>::infinity());
  }
  if (covariance.size() > 0) {
    fit.covariance.assign(m, std::vector<double>(m));
    for (std::size_t a = 0; a < m; ++a) {
      for (std::size_t b = 0; b < m; ++b) {
        fit.covariance[a][b] = covariance(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) *
                               evaluator.free()[a].scale * evaluator.free()[b].scale;
      }
    }
  }
  fit.predictions = cache.at(theta);
  return fit;
}

double robust_sigma(std::span<const double> r, std::span<const std::size_t> slots) {
  std::vector<double> a;
  for (std::size_t k : slots) a.push_back(std::abs(r[k]));
  if (a.empty()) return 0.0;
  auto mid = a.begin() + static_cast<std::ptrdiff_t>(a.size() / 2);
  std::nth_element(a.begin(), mid, a.end());
  return 1.4826 * *mid;
}

}  // namespace swum
