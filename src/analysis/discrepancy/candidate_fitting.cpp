#include "analysis/discrepancy/candidate_fitting.h"

#include <algorithm>
#include <cmath>

#include "formats/number_format.h"

namespace swum {

double sum_of_squares(std::span<const double> r, std::span<const std::size_t> slots) {
  double s = 0.0;
  for (std::size_t k : slots) s += r[k] * r[k];
  return s;
}

double rms_of(std::span<const double> r, std::span<const std::size_t> slots) {
  return slots.empty() ? 0.0 : std::sqrt(sum_of_squares(r, slots) / static_cast<double>(slots.size()));
}

double delta_bic(double sse_new, double sse_old, std::size_t n, int added) {
  const double nd = static_cast<double>(n);
  return nd * std::log(std::max(sse_new, 1e-300) / std::max(sse_old, 1e-300)) + added * std::log(nd);
}

double cauchy_cost(std::span<const double> r, std::span<const std::size_t> slots, double a) {
  double cost = 0.0;
  for (std::size_t k : slots) cost += a > 0.0 ? a * a * std::log1p(r[k] * r[k] / (a * a)) : r[k] * r[k];
  return cost;
}

std::vector<Screened> screen_candidates(const MotorParameters& current,
                                        const std::vector<std::optional<FreeParameter>>& candidates,
                                        const Predictions& current_predictions,
                                        const std::vector<double>& current_residuals, const ResidualModel& model,
                                        std::span<const std::size_t> train, const ScreeningSettings& settings,
                                        const BatchPredictor& predict) {
  const std::size_t n = train.size();
  const double sse0 = sum_of_squares(current_residuals, train);
  const double robust0 = cauchy_cost(current_residuals, train, settings.scale);
  std::vector<std::size_t> active;
  std::vector<Screened> best(candidates.size());
  std::vector<Screened> last(candidates.size());
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    best[c] = {0.0, sse0, robust0, current_predictions, current_residuals};
    if (candidates[c]) active.push_back(c);
  }
  const std::vector<Screened> start = best;  // theta 0: where the first secant starts
  std::vector<double> thetas(candidates.size(), 1.0);
  for (int step = 0; step <= settings.steps && !active.empty(); ++step) {
    std::vector<MotorParameters> models;
    for (std::size_t c : active) {
      MotorParameters p = current;
      const FreeParameter& e = *candidates[c];
      e.apply(p, e.origin + thetas[c] * e.scale);
      models.push_back(p);
    }
    const std::vector<Predictions> batch = predict(models);
    std::vector<std::pair<double, std::size_t>> promising;  // (predicted SSE, candidate)
    for (std::size_t a = 0; a < active.size(); ++a) {
      const std::size_t c = active[a];
      const FreeParameter& e = *candidates[c];
      Screened s{thetas[c], 0.0, 0.0, batch[a], model.residuals(batch[a])};
      s.sse = sum_of_squares(s.residuals, train);
      s.robust = cauchy_cost(s.residuals, train, settings.scale);
      // Secant through the last two evaluations (the first: the current model at theta 0).
      const Screened& from = step == 0 ? start[c] : last[c];
      const double dtheta = s.theta - from.theta;
      // Iteratively reweighted Gauss-Newton step of the Cauchy cost (weights 1/(1 + r^2/a^2)).
      double jr = 0.0, jj = 0.0, wjr = 0.0, wjj = 0.0;
      for (std::size_t k : train) {
        const double j = (s.residuals[k] - from.residuals[k]) / dtheta;
        const double w = settings.scale > 0.0
                             ? 1.0 / (1.0 + s.residuals[k] * s.residuals[k] / (settings.scale * settings.scale))
                             : 1.0;
        jr += j * s.residuals[k];
        jj += j * j;
        wjr += w * j * s.residuals[k];
        wjj += w * j * j;
      }
      if (s.robust < best[c].robust) best[c] = s;
      double lo = (e.lower - e.origin) / e.scale;
      double hi = (e.upper - e.origin) / e.scale;
      if (lo > hi) std::swap(lo, hi);
      double next = wjj > 0.0 ? s.theta - wjr / wjj : s.theta;
      next = std::clamp(next, lo, hi);
      if (std::abs(next - s.theta) < 1e-3) next = s.theta + 1e-3;
      thetas[c] = next;
      // Gauss-Newton prediction of the minimum: screening goes on only for candidates that
      // could pass the BIC margin, at most the `follow_up` best.
      const double predicted = std::min(best[c].sse, jj > 0.0 ? s.sse - jr * jr / jj : s.sse);
      if (delta_bic(predicted, sse0, n, 1) < -settings.bic_margin) promising.emplace_back(predicted, c);
      last[c] = std::move(s);
    }
    std::sort(promising.begin(), promising.end());
    if (!settings.families.empty()) {
      std::vector<std::size_t> seen;
      std::erase_if(promising, [&](const std::pair<double, std::size_t>& p) {
        const std::size_t family = settings.families[p.second];
        if (std::find(seen.begin(), seen.end(), family) != seen.end()) return true;
        seen.push_back(family);
        return false;
      });
    }
    if (promising.size() > settings.follow_up) promising.resize(settings.follow_up);
    active.clear();
    for (const auto& p : promising) active.push_back(p.second);
  }
  return best;
}

std::string describe_evidence(double bic, const HeldOutEvidence& e) {
  return format_numbers("delta BIC %+.4g; held-out: ", bic) + std::to_string(e.improved) + " of " +
         std::to_string(e.points) + format_numbers(" points better, p = %.2g", e.p_value) +
         format_numbers(" (signed-rank %.2g, sign-flip %.2g)", e.signed_rank_p, e.sign_flip_p) +
         format_numbers("; RMS gap %.3g %%", 100.0 * e.rms_before) +
         format_numbers(" -> %.3g %% (reduction %.0f %%", 100.0 * e.rms_after, 100.0 * e.reduction) +
         format_numbers(", 90 %% interval %.0f..%.0f %%)", 100.0 * e.reduction_low, 100.0 * e.reduction_high);
}

namespace {

// The Cauchy M-estimate (parameter_fit.h) from a first fit `ls` (at the round's scale), rescaled
// by what that fit leaves. Its cost is not convex where a reading sits on a step of the model (a
// dead-zone edge, a jump across the fold): the last parameter is first scanned around the
// least-squares value (+-10, 25, 50 % of its offset from neutral, one batch) and the fit starts
// at the lowest robust cost.
ParameterFit robust_refit(const ParameterEvaluator& eval, const ResidualModel& model,
                          std::span<const std::size_t> train, const ParameterFit& ls, int max_iterations) {
  const double scale = kCauchyEfficiencyScale * robust_sigma(model.residuals(ls.predictions), train);
  if (!(scale > 0.0)) return ls;
  auto cost_of = [&](const Predictions& p) {
    double cost = 0.0;
    for (std::size_t k : train) {
      const double r = model.residual(k, p);
      cost += scale * scale * std::log1p(r * r / (scale * scale));
    }
    return cost;
  };
  const FreeParameter& e = eval.free().back();
  const double offset = ls.values.back() - e.origin;
  std::vector<std::vector<double>> starts;
  for (double f : {-0.5, -0.25, -0.1, 0.1, 0.25, 0.5}) {
    std::vector<double> v = ls.values;
    v.back() = std::clamp(ls.values.back() + f * offset, std::min(e.lower, e.upper), std::max(e.lower, e.upper));
    starts.push_back(v);
  }
  const std::vector<Predictions> scanned = eval.evaluate(starts);
  std::vector<double> start = ls.values;
  const Predictions* start_predictions = &ls.predictions;
  double best = cost_of(ls.predictions);
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const double cost = cost_of(scanned[k]);
    if (cost < best) {
      best = cost;
      start = starts[k];
      start_predictions = &scanned[k];
    }
  }
  ParameterFit robust = fit_parameters(eval, model, train, start, max_iterations, start_predictions, scale);
  return robust.ok ? robust : ls;
}

}  // namespace

ParameterFit fit_candidate(const ParameterEvaluator& eval, const ResidualModel& model,
                           std::span<const std::size_t> train, const std::vector<double>& start,
                           const Predictions* start_predictions, double round_scale, bool robust, int max_iterations) {
  ParameterFit fit = fit_parameters(eval, model, train, start, max_iterations, start_predictions,
                                    robust ? round_scale : 0.0);
  if (fit.ok && robust) fit = robust_refit(eval, model, train, fit, max_iterations);
  return fit;
}

}  // namespace swum
