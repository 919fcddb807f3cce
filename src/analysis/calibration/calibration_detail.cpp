#include "analysis/calibration/calibration_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "analysis/calibration/calibration_candidates.h"
#include "formats/number_format.h"

namespace swum {
namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();
}  // namespace

namespace {

std::vector<FreeParameter> free_parameters(const std::vector<std::string>& names,
                                           const std::vector<std::string>& fallback, const MotorParameters& prior,
                                           std::string_view what) {
  std::vector<FreeParameter> out;
  const std::vector<std::string>& list = names.empty() ? fallback : names;
  for (const std::string& name : list) {
    const CalibrationCandidate* c = find_calibration_candidate(name);
    if (c == nullptr) {
      throw std::invalid_argument("--" + std::string(what) + ": '" + name +
                                  "' is not a parameter calibration can fit (" + calibration_candidate_names() + ")");
    }
    for (const FreeParameter& f : out) {
      if (f.name == name) throw std::invalid_argument("--" + std::string(what) + ": '" + name + "' is listed twice");
    }
    out.push_back(calibration_free_parameter(*c, prior));
  }
  return out;
}

}  // namespace

std::vector<FreeParameter> calibration_pool(const CalibrationOptions& options, const MotorParameters& prior) {
  std::vector<std::string> applicable;
  for (const CalibrationCandidate* c : applicable_candidates(prior)) applicable.emplace_back(c->name);
  std::vector<FreeParameter> pool = options.free.empty()
                                        ? free_parameters(options.candidates, applicable, prior, "candidates")
                                        : free_parameters(options.free, {}, prior, "free");
  if (pool.empty()) throw std::invalid_argument("no parameter to fit");
  return pool;
}

namespace {

// Expected standard errors (in spreads) of the parameters `cols` of J (theta units, rows
// divided by their noise): sqrt(diag (J'J)^-1); empty when J'J is singular there.
Eigen::VectorXd expected_errors(const Eigen::MatrixXd& j, const std::vector<Eigen::Index>& cols) {
  Eigen::MatrixXd js(j.rows(), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t k = 0; k < cols.size(); ++k) js.col(static_cast<Eigen::Index>(k)) = j.col(cols[k]);
  const Eigen::MatrixXd information = js.transpose() * js;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(information);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * ldlt.vectorD().maxCoeff())) return {};
  const Eigen::MatrixXd inverse = ldlt.solve(Eigen::MatrixXd::Identity(information.rows(), information.cols()));
  return inverse.diagonal().cwiseSqrt();
}

}  // namespace

std::vector<std::size_t> select_free_set(const Eigen::MatrixXd& j, const std::vector<FreeParameter>& pool,
                                         const CalibrationOptions& options, std::vector<CandidateInformation>& report) {
  const double limit = options.max_spread_fraction;
  report.clear();
  for (Eigen::Index c = 0; c < j.cols(); ++c) {
    const double norm = j.col(c).norm();
    report.push_back({pool[static_cast<std::size_t>(c)].name, norm > 0.0 ? 1.0 / norm : kInfinity, false, ""});
  }
  std::vector<std::size_t> selected;
  std::vector<Eigen::Index> cols;
  for (std::size_t c = 0; c < pool.size(); ++c) {
    if (static_cast<int>(selected.size()) >= options.max_free) {
      report[c].reason = "the free set is full (--max-free " + std::to_string(options.max_free) + ")";
      continue;
    }
    if (!(report[c].expected_standard_error <= limit)) {
      report[c].reason = format_numbers("insensitive: expected standard error alone %.3g spreads (limit %.2g)",
                                        report[c].expected_standard_error, limit);
      continue;
    }
    std::vector<Eigen::Index> trial = cols;
    trial.push_back(static_cast<Eigen::Index>(c));
    const Eigen::VectorXd se = expected_errors(j, trial);
    if (se.size() == 0 || !(se.maxCoeff() <= limit)) {
      // Collinear with the selected set: name the selected parameter it is most aligned with.
      std::string with;
      double best_cos = -1.0;
      for (std::size_t s : selected) {
        const auto ic = static_cast<Eigen::Index>(c), is = static_cast<Eigen::Index>(s);
        const double cosine = std::abs(j.col(ic).dot(j.col(is))) / (j.col(ic).norm() * j.col(is).norm());
        if (cosine > best_cos) {
          best_cos = cosine;
          with = pool[s].name;
        }
      }
      report[c].reason = se.size() == 0 ? "collinear with " + with + " (singular information)"
                                        : "collinear with " + with +
                                              format_numbers(": expected standard error with the selected set "
                                                             "%.3g spreads (|cos| %.3f)",
                                                             se.maxCoeff(), best_cos);
      continue;
    }
    report[c].selected = true;
    selected.push_back(c);
    cols.push_back(static_cast<Eigen::Index>(c));
  }
  return selected;
}

namespace {
double rms_of(const std::vector<double>& r, const std::vector<std::size_t>& slots) {
  if (slots.empty()) return 0.0;
  double s = 0.0;
  for (std::size_t k : slots) s += r[k] * r[k];
  return std::sqrt(s / static_cast<double>(slots.size()));
}
}  // namespace

void score_on_measurements(const MeasurementSet& set, const ResidualModel& model, const std::vector<std::size_t>& train,
                           const std::vector<std::size_t>& test, const CalibrationOptions& options,
                           CalibrationResult& result) {
  const std::vector<double> r_prior = model.residuals(result.prior_predictions);
  const std::vector<double> r_fit = model.residuals(result.fitted_predictions);
  result.train_rms_prior = rms_of(r_prior, train);
  result.held_out_rms_prior = rms_of(r_prior, test);
  result.train_rms = rms_of(r_fit, train);
  result.held_out_rms = rms_of(r_fit, test);
  result.held_out_evidence = compare_held_out(set, model, r_prior, r_fit, test, options.split.seed);
}

std::vector<std::vector<double>> fit_starts(const std::vector<double>& start, const std::vector<FreeParameter>& free,
                                            int count, std::mt19937_64& rng) {
  std::vector<std::vector<double>> starts{start};
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int s = 1; s < count; ++s) {
    std::vector<double> v = start;
    for (std::size_t k = 0; k < free.size(); ++k) {
      v[k] = std::clamp(free[k].origin + u(rng) * free[k].scale, std::min(free[k].lower, free[k].upper),
                        std::max(free[k].lower, free[k].upper));
    }
    starts.push_back(v);
  }
  return starts;
}

bool at_bound(const FreeParameter& f, double value) {
  const double tolerance = 1e-6 * std::abs(f.scale);
  return std::abs(value - f.lower) <= tolerance || std::abs(value - f.upper) <= tolerance;
}

Undetermined least_determined(const std::vector<double>& values, const std::vector<double>& standard_errors,
                              const std::vector<FreeParameter>& free, const CalibrationOptions& options) {
  for (std::size_t k = 0; k < free.size(); ++k) {
    if (at_bound(free[k], values[k])) {
      return {k, format_numbers("the fit ran into its bound %.6g (bounds %.6g .. %.6g, prior %.6g): the data push it "
                                "past what this design can be (a missing effect, or a measurement protocol the model "
                                "does not follow); held at its prior",
                                values[k], std::min(free[k].lower, free[k].upper),
                                std::max(free[k].lower, free[k].upper), free[k].origin)};
    }
  }
  Undetermined worst;
  double worst_ratio = options.max_spread_fraction;
  for (std::size_t k = 0; k < free.size(); ++k) {
    const double ratio = standard_errors[k] / std::abs(free[k].scale);
    if (!(ratio <= worst_ratio)) {
      worst_ratio = std::isfinite(ratio) ? ratio : kInfinity;
      worst.index = k;
      worst.reason = std::isfinite(ratio)
                         ? format_numbers("standard error %.3g is %.2g prior spreads (limit %.2g): held at its prior",
                                          standard_errors[k], ratio, options.max_spread_fraction)
                         : std::string("the data leave it undetermined (singular information): held at its prior");
      if (!std::isfinite(ratio)) break;
    }
  }
  return worst;
}

CalibratedParameter hold_at_prior(const Undetermined& which, std::vector<FreeParameter>& free,
                                  std::vector<double>& start) {
  const std::size_t k = *which.index;
  const FreeParameter& f = free[k];
  CalibratedParameter held{f.name,  f.unit, f.origin, std::abs(f.scale), f.origin, kInfinity, f.lower,
                           f.upper, false,  false,    which.reason};
  start.erase(start.begin() + static_cast<std::ptrdiff_t>(k));
  free.erase(free.begin() + static_cast<std::ptrdiff_t>(k));
  return held;
}

}  // namespace swum
