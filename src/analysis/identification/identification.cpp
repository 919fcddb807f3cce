#include "analysis/identification/identification.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include <ceres/ceres.h>
#include <Eigen/Dense>

#include "formats/number_format.h"
#include "model/modal/modal_constants.h"
#include "model/motor_model.h"

namespace swum {
namespace {

constexpr int kP = kNonlinearParameterCount;
constexpr std::array<NonlinearParameter, kP> kAll = {NonlinearParameter::c111, NonlinearParameter::c1111,
                                                     NonlinearParameter::e311, NonlinearParameter::e3111};

// Everything a residual needs besides the parameter vector (read-only during a solve).
struct FitContext {
  ModalConstants constants;
  StatorParameters prior;
  HarmonicBalanceOptions hb_options;
  std::array<double, kP> scale{};
};

StatorParameters with_theta(const FitContext& ctx, const double* theta) {
  StatorParameters s = ctx.prior;
  for (int p = 0; p < kP; ++p) set_nonlinear_parameter(s, kAll[p], theta[p] * ctx.scale[p]);
  return s;
}

// One amplitude of one data point: r = (predicted - measured) / normaliser, parameters in units
// of their scale (theta_p = p / scale_p). Analytic Jacobian from the harmonic balance
// (implicit function theorem, harmonic_balance.cpp).
class AmplitudeResidual final : public ceres::SizedCostFunction<1, kP> {
 public:
  AmplitudeResidual(const FitContext* ctx, StatorMode mode, double amplitude_v, double frequency_hz, double measured_um,
                    double normaliser_um)
      : ctx_(ctx),
        mode_(mode),
        amplitude_v_(amplitude_v),
        frequency_hz_(frequency_hz),
        measured_um_(measured_um),
        normaliser_um_(normaliser_um) {}

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const FreeStatorHarmonicBalance hb(ctx_->constants, with_theta(*ctx_, parameters[0]), ctx_->hb_options);
    const auto branch = predicted_branch(hb, mode_, amplitude_v_, frequency_hz_, measured_um_);
    if (!branch) return false;
    residuals[0] = (branch->tip_amplitude_um - measured_um_) / normaliser_um_;
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      for (int p = 0; p < kP; ++p) {
        jacobians[0][p] = branch->tip_amplitude_sensitivity_um[p] * ctx_->scale[p] / normaliser_um_;
      }
    }
    return std::isfinite(residuals[0]);
  }

 private:
  const FitContext* ctx_;
  StatorMode mode_;
  double amplitude_v_, frequency_hz_, measured_um_, normaliser_um_;
};

struct Observation {
  StatorMode mode;
  double amplitude_v, frequency_hz, measured_um, normaliser_um;
};

// Residuals and Jacobian (rows: observations, columns: theta) at theta; false if any point has
// no harmonic-balance solution.
bool evaluate_all(const FitContext& ctx, const std::vector<Observation>& obs, const std::array<double, kP>& theta,
                  Eigen::VectorXd& r, Eigen::MatrixXd& j) {
  r.resize(static_cast<Eigen::Index>(obs.size()));
  j.resize(static_cast<Eigen::Index>(obs.size()), kP);
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const Observation& o = obs[i];
    AmplitudeResidual cost(&ctx, o.mode, o.amplitude_v, o.frequency_hz, o.measured_um, o.normaliser_um);
    const double* blocks[1] = {theta.data()};
    double row[kP];
    double* jac[1] = {row};
    if (!cost.Evaluate(blocks, &r[static_cast<Eigen::Index>(i)], jac)) return false;
    for (int p = 0; p < kP; ++p) j(static_cast<Eigen::Index>(i), p) = row[p];
  }
  return true;
}

struct FitOutcome {
  bool ok = false;
  std::array<double, kP> theta{};
  double cost = std::numeric_limits<double>::infinity();
  int starts = 0;
};

// Multi-start bounded Levenberg-Marquardt over the free parameters (others fixed at start).
FitOutcome fit(const FitContext& ctx, const std::vector<Observation>& obs, const std::array<bool, kP>& free,
               const std::array<double, kP>& theta_prior, const IdentificationOptions& options, std::mt19937_64& rng) {
  FitOutcome best;
  std::vector<int> fixed;
  for (int p = 0; p < kP; ++p) {
    if (!free[p]) fixed.push_back(p);
  }
  if (fixed.size() == static_cast<std::size_t>(kP)) return best;
  const double bound = options.bound_factor;
  auto uniform = [&] {  // portable: 53 random bits -> [0, 1)
    return static_cast<double>(rng() >> 11) * 0x1.0p-53;
  };
  for (int start = 0; start < std::max(options.starts, 1); ++start) {
    std::array<double, kP> theta = theta_prior;
    for (int p = 0; p < kP; ++p) {
      if (!free[p]) continue;
      if (start == 1) theta[p] = 0.0;  // the linear model
      if (start >= 2) theta[p] = options.start_spread * (2.0 * uniform() - 1.0);
      theta[p] = std::clamp(theta[p], -bound, bound);
    }
    ceres::Problem problem;
    for (const Observation& o : obs) {
      problem.AddResidualBlock(new AmplitudeResidual(&ctx, o.mode, o.amplitude_v, o.frequency_hz, o.measured_um,
                                                     o.normaliser_um),
                               nullptr, theta.data());
    }
    for (int p = 0; p < kP; ++p) {
      problem.SetParameterLowerBound(theta.data(), p, -bound);
      problem.SetParameterUpperBound(theta.data(), p, bound);
    }
    if (!fixed.empty()) {
      problem.SetManifold(theta.data(), new ceres::SubsetManifold(kP, fixed));
    }
    ceres::Solver::Options so;
    so.minimizer_type = ceres::TRUST_REGION;
    so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = options.max_iterations;
    so.function_tolerance = 1e-14;
    so.gradient_tolerance = 1e-16;
    so.parameter_tolerance = 1e-12;
    so.num_threads = 1;
    so.logging_type = ceres::SILENT;
    so.minimizer_progress_to_stdout = false;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    ++best.starts;
    if (!summary.IsSolutionUsable()) continue;
    if (summary.final_cost < best.cost) {
      best.ok = true;
      best.cost = summary.final_cost;
      best.theta = theta;
    }
  }
  return best;
}

std::string short_number(double v) { return format_number(v, "%.3g"); }

}  // namespace

std::string_view nonlinear_parameter_key(NonlinearParameter p) {
  switch (p) {
    case NonlinearParameter::c111: return "c111_pa";
    case NonlinearParameter::c1111: return "c1111_pa";
    case NonlinearParameter::e311: return "e311_c_per_v_m";
    case NonlinearParameter::e3111: return "e3111_c_per_v_m";
  }
  return "";
}

double nonlinear_parameter_value(const StatorParameters& s, NonlinearParameter p) {
  switch (p) {
    case NonlinearParameter::c111: return s.c111_pa;
    case NonlinearParameter::c1111: return s.c1111_pa;
    case NonlinearParameter::e311: return s.e311_c_per_v_m;
    case NonlinearParameter::e3111: return s.e3111_c_per_v_m;
  }
  return 0.0;
}

void set_nonlinear_parameter(StatorParameters& s, NonlinearParameter p, double value) {
  switch (p) {
    case NonlinearParameter::c111: s.c111_pa = value; break;
    case NonlinearParameter::c1111: s.c1111_pa = value; break;
    case NonlinearParameter::e311: s.e311_c_per_v_m = value; break;
    case NonlinearParameter::e3111: s.e3111_c_per_v_m = value; break;
  }
}

std::optional<ModeBranch> predicted_branch(const FreeStatorHarmonicBalance& hb, StatorMode mode, double amplitude_v,
                                           double frequency_hz, std::optional<double> measured_um) {
  const ModeResponse r = hb.solve_mode(mode, amplitude_v, frequency_hz);
  const ModeBranch* best = nullptr;
  double best_score = std::numeric_limits<double>::infinity();
  for (int pass = 0; pass < 2 && best == nullptr; ++pass) {  // stable first, then any
    for (const ModeBranch& b : r.branches) {
      if (pass == 0 && !b.stable) continue;
      const double score = measured_um ? std::abs(b.tip_amplitude_um - *measured_um) : -b.tip_amplitude_um;
      if (score < best_score) {
        best_score = score;
        best = &b;
      }
    }
  }
  if (best == nullptr) return std::nullopt;
  return *best;
}

IdentificationResult identify_nonlinear_parameters(const MotorParameters& prior,
                                                   std::span<const AmplitudeMeasurement> data,
                                                   const IdentificationOptions& options) {
  IdentificationResult result;
  const MotorModel model(prior);  // validates
  FitContext ctx;
  ctx.constants = model.constants();
  ctx.prior = prior.stator;
  ctx.hb_options = options.harmonic_balance;
  const StatorParameters table2{};  // Table-2 magnitudes (model_spec §7.2) set the scale floor
  std::array<double, kP> theta_prior{};
  for (int p = 0; p < kP; ++p) {
    ParameterEstimate& e = result.parameters[p];
    e.parameter = kAll[p];
    e.key = nonlinear_parameter_key(kAll[p]);
    e.prior = nonlinear_parameter_value(prior.stator, kAll[p]);
    e.value = e.prior;
    e.scale = std::max(std::abs(e.prior), std::abs(nonlinear_parameter_value(table2, kAll[p])));
    ctx.scale[p] = e.scale;
    theta_prior[p] = e.prior / e.scale;
  }

  // Observations with their normalisers (relative residuals with a floor, see header).
  double max_amplitude[2] = {0.0, 0.0};
  for (const AmplitudeMeasurement& m : data) {
    if (m.tip_normal_um) max_amplitude[0] = std::max(max_amplitude[0], std::abs(*m.tip_normal_um));
    if (m.tip_tangential_um) max_amplitude[1] = std::max(max_amplitude[1], std::abs(*m.tip_tangential_um));
  }
  std::vector<Observation> obs;
  for (const AmplitudeMeasurement& m : data) {
    for (int axis = 0; axis < 2; ++axis) {
      const std::optional<double>& value = axis == 0 ? m.tip_normal_um : m.tip_tangential_um;
      if (!value) continue;
      const double floor = std::max(options.amplitude_floor_fraction * max_amplitude[axis], 1e-9);
      obs.push_back(
          {static_cast<StatorMode>(axis), m.amplitude_v, m.frequency_hz, *value, std::max(std::abs(*value), floor)});
    }
  }
  result.residual_count = static_cast<int>(obs.size());
  if (obs.size() < static_cast<std::size_t>(kP)) {
    result.failure = "need at least " + std::to_string(kP) + " amplitude values, got " + std::to_string(obs.size());
    return result;
  }

  std::mt19937_64 rng(options.seed);
  std::array<bool, kP> free{true, true, true, true};
  std::array<double, kP> theta = theta_prior;
  bool fitted_once = false;
  while (std::any_of(free.begin(), free.end(), [](bool f) { return f; })) {
    const FitOutcome outcome = fit(ctx, obs, free, theta_prior, options, rng);
    ++result.rounds;
    result.starts_run += outcome.starts;
    if (!outcome.ok) {
      result.failure = "no start converged (the harmonic balance failed at some data point)";
      return result;
    }
    fitted_once = true;
    theta = outcome.theta;
    Eigen::VectorXd r;
    Eigen::MatrixXd j;
    if (!evaluate_all(ctx, obs, theta, r, j)) {
      result.failure = "the harmonic balance failed at the fitted parameters";
      return result;
    }
    std::vector<int> idx;
    for (int p = 0; p < kP; ++p) {
      if (free[p]) idx.push_back(p);
    }
    const int n_free = static_cast<int>(idx.size());
    const int dof = static_cast<int>(obs.size()) - n_free;
    const double s2 = dof > 0 ? r.squaredNorm() / dof : std::numeric_limits<double>::infinity();
    std::vector<int> fixed_idx;
    for (int p = 0; p < kP; ++p) {
      if (!free[p]) fixed_idx.push_back(p);
    }
    const Eigen::MatrixXd h = j.transpose() * j;  // information, theta units (all four)
    Eigen::MatrixXd h_ii(n_free, n_free);
    Eigen::MatrixXd h_if(n_free, static_cast<Eigen::Index>(fixed_idx.size()));
    for (int k = 0; k < n_free; ++k) {
      for (int l = 0; l < n_free; ++l) h_ii(k, l) = h(idx[k], idx[l]);
      for (std::size_t l = 0; l < fixed_idx.size(); ++l) {
        h_if(k, static_cast<Eigen::Index>(l)) = h(idx[k], fixed_idx[l]);
      }
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(h_ii);
    const Eigen::VectorXd lambda = eig.eigenvalues();
    const double lambda_max = std::max(lambda.maxCoeff(), 0.0);
    // Pseudo-inverse over the non-flat directions; a parameter on a flat one has no error bar.
    Eigen::MatrixXd h_inv = Eigen::MatrixXd::Zero(n_free, n_free);
    std::vector<bool> on_flat(n_free, false);
    for (int m = 0; m < n_free; ++m) {
      const Eigen::VectorXd v = eig.eigenvectors().col(m);
      if (lambda[m] <= options.flat_eigenvalue_ratio * lambda_max) {
        for (int k = 0; k < n_free; ++k) on_flat[k] = on_flat[k] || v[k] * v[k] > 1e-6;
      } else {
        h_inv += v * v.transpose() / lambda[m];
      }
    }
    // Standard errors: noise part s^2 H_II^-1 plus the "consider" part of the parameters held
    // at their priors (each uncertain by its scale, i.e. 1 in theta units): S S^T with
    // S = H_II^-1 H_IF, the shift of the estimate per unit error of a held parameter.
    const Eigen::MatrixXd shift = h_inv * h_if;
    int worst = -1;
    double worst_ratio = 0.0;
    std::string worst_reason;
    for (int k = 0; k < n_free; ++k) {
      const bool flat = on_flat[k];
      const double variance = s2 * h_inv(k, k) + shift.row(k).squaredNorm();
      const int p = idx[k];
      ParameterEstimate& e = result.parameters[p];
      e.value = theta[p] * e.scale;
      e.standard_error = (flat || !std::isfinite(s2)) ? std::numeric_limits<double>::infinity()
                                                      : std::sqrt(variance) * e.scale;
      const double size = std::max(std::abs(e.value), e.scale);
      const double ratio = e.standard_error / size;
      if (ratio >= options.max_relative_standard_error && ratio > worst_ratio) {
        worst = p;
        worst_ratio = ratio;
        worst_reason = flat                 ? "flat direction of J^T J (the data do not depend on it)"
                       : !std::isfinite(s2) ? "no degrees of freedom left for a standard error"
                                            : "standard error too large for its size";
      }
    }
    if (worst < 0) break;
    free[worst] = false;  // keep at the prior, refit the others
    theta_prior[worst] = result.parameters[worst].prior / result.parameters[worst].scale;
    ParameterEstimate& e = result.parameters[worst];
    if (std::isfinite(e.standard_error)) {
      e.reason = worst_reason + " (fitted " + short_number(e.value) + ", standard error " +
                 short_number(e.standard_error) + ")";
    } else {
      e.reason = worst_reason;
    }
    e.value = e.prior;
    e.standard_error = std::numeric_limits<double>::infinity();
    theta = theta_prior;  // fixed entries back at the prior
  }
  if (!fitted_once) {
    result.failure = "nothing to fit";
    return result;
  }

  // Final state: identified parameters fitted, the rest at their priors.
  result.fitted_stator = prior.stator;
  for (int p = 0; p < kP; ++p) {
    ParameterEstimate& e = result.parameters[p];
    e.identifiable = free[p];
    if (!free[p]) {
      e.value = e.prior;
      e.standard_error = std::numeric_limits<double>::infinity();
      e.significant = false;
    } else {
      e.significant = std::abs(e.value) > options.significance_sigmas * e.standard_error;
    }
    set_nonlinear_parameter(result.fitted_stator, kAll[p], e.value);
    theta[p] = e.value / e.scale;
  }

  // Residual report and the information spectrum at the final parameters (all four).
  Eigen::VectorXd r;
  Eigen::MatrixXd j;
  if (!evaluate_all(ctx, obs, theta, r, j)) {
    result.failure = "the harmonic balance failed at the fitted parameters";
    return result;
  }
  result.rms_relative_residual = std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(j.transpose() * j);
  for (int m = 0; m < kP; ++m) {
    result.information_eigenvalues[m] = eig.eigenvalues()[m];
    for (int p = 0; p < kP; ++p) result.information_eigenvectors[m][p] = eig.eigenvectors()(p, m);
  }
  const FreeStatorHarmonicBalance hb(ctx.constants, result.fitted_stator, ctx.hb_options);
  double sum2[2] = {0.0, 0.0};
  int count[2] = {0, 0};
  for (const AmplitudeMeasurement& m : data) {
    PointPrediction pp;
    pp.measurement = m;
    if (m.tip_normal_um) {
      if (auto b = predicted_branch(hb, StatorMode::l1, m.amplitude_v, m.frequency_hz, m.tip_normal_um)) {
        pp.predicted_normal_um = b->tip_amplitude_um;
        sum2[0] += std::pow(b->tip_amplitude_um - *m.tip_normal_um, 2);
        ++count[0];
      }
    }
    if (m.tip_tangential_um) {
      if (auto b = predicted_branch(hb, StatorMode::b2, m.amplitude_v, m.frequency_hz, m.tip_tangential_um)) {
        pp.predicted_tangential_um = b->tip_amplitude_um;
        sum2[1] += std::pow(b->tip_amplitude_um - *m.tip_tangential_um, 2);
        ++count[1];
      }
    }
    result.predictions.push_back(pp);
  }
  if (count[0] > 0) result.rms_normal_um = std::sqrt(sum2[0] / count[0]);
  if (count[1] > 0) result.rms_tangential_um = std::sqrt(sum2[1] / count[1]);
  result.ok = true;
  return result;
}

}  // namespace swum
