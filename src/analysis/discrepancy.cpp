#include "analysis/discrepancy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <random>
#include <stdexcept>
#include <tuple>

#include "analysis/effect_fit.h"

namespace swum {
namespace {

std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, a, b, c);
  return text;
}

// Held-out rows: operating points (a point's repeats stay together) in a seeded random order,
// every `every`-th held out.
std::vector<bool> held_out_rows(const MeasurementSet& set, int every, std::uint64_t seed) {
  std::map<std::tuple<double, double, double, double>, std::size_t> group_of;
  std::vector<std::size_t> group(set.rows.size());
  for (std::size_t i = 0; i < set.rows.size(); ++i) {
    const Measurement& m = set.rows[i];
    const auto key = std::make_tuple(m.vpp, m.frequency_hz, m.load_n, m.time_s.value_or(0.0));
    group[i] = group_of.try_emplace(key, group_of.size()).first->second;
  }
  std::vector<std::size_t> permutation(group_of.size());
  std::iota(permutation.begin(), permutation.end(), std::size_t{0});
  std::mt19937_64 rng(seed);
  for (std::size_t i = permutation.size(); i > 1; --i) {  // Fisher-Yates, portable
    std::swap(permutation[i - 1], permutation[rng() % i]);
  }
  std::vector<bool> held_group(group_of.size(), false);
  for (std::size_t k = 0; k < permutation.size(); ++k) {
    held_group[permutation[k]] = every > 1 && k % static_cast<std::size_t>(every) == static_cast<std::size_t>(every) - 1;
  }
  std::vector<bool> held(set.rows.size());
  for (std::size_t i = 0; i < held.size(); ++i) held[i] = held_group[group[i]];
  return held;
}

double sum_of_squares(const std::vector<double>& r, const std::vector<std::size_t>& slots) {
  double s = 0.0;
  for (std::size_t k : slots) s += r[k] * r[k];
  return s;
}

double rms(const std::vector<double>& r, const std::vector<std::size_t>& slots) {
  return slots.empty() ? 0.0 : std::sqrt(sum_of_squares(r, slots) / static_cast<double>(slots.size()));
}

// Paired t statistic of r0^2 - r1^2 over the held-out slots (> 0: the candidate is better).
double held_out_t(const std::vector<double>& r0, const std::vector<double>& r1,
                  const std::vector<std::size_t>& slots) {
  const double m = static_cast<double>(slots.size());
  if (slots.size() < 3) return 0.0;
  double mean = 0.0;
  for (std::size_t k : slots) mean += r0[k] * r0[k] - r1[k] * r1[k];
  mean /= m;
  double var = 0.0;
  for (std::size_t k : slots) {
    const double d = r0[k] * r0[k] - r1[k] * r1[k] - mean;
    var += d * d;
  }
  var /= m - 1.0;
  if (var <= 0.0) return mean > 0.0 ? 1e9 : 0.0;
  return mean / std::sqrt(var / m);
}

// Schwarz criterion difference for `added` extra parameters: n ln(SSE1/SSE0) + added ln n.
double delta_bic(double sse_new, double sse_old, std::size_t n, int added) {
  const double nd = static_cast<double>(n);
  return nd * std::log(std::max(sse_new, 1e-300) / std::max(sse_old, 1e-300)) + added * std::log(nd);
}

struct Screened {
  double theta = 0.0;
  double sse = 0.0;
  Predictions predictions;
  std::vector<double> residuals;
};

}  // namespace

DiscrepancyResult run_discrepancy(const MotorParameters& baseline, const MeasurementSet& set,
                                  const DiscrepancyOptions& options, const ParallelFor& parallel) {
  std::vector<const CandidateEffect*> candidates;
  if (options.candidates.empty()) {
    for (const auto& e : candidate_effects()) candidates.push_back(&e);
  } else {
    for (const std::string& name : options.candidates) {
      const CandidateEffect* e = find_candidate_effect(name);
      if (e == nullptr) {
        throw std::invalid_argument("unknown effect '" + name + "' (known: " +
                                    candidate_effect_names() + ")");
      }
      candidates.push_back(e);
    }
  }
  DiscrepancyResult result;
  result.held_out = held_out_rows(set, options.held_out_every, options.split_seed);
  const ResidualModel model(set, options.floor_fraction);
  std::vector<std::size_t> train, test;
  for (std::size_t k = 0; k < model.slots().size(); ++k) {
    (result.held_out[model.slots()[k].row] ? test : train).push_back(k);
  }
  const std::size_t n = train.size();
  auto predict = [&](const std::vector<MotorParameters>& models) {
    result.model_evaluations += static_cast<int>(models.size());
    return predict_points(models, set.rows, options.prediction, parallel);
  };

  MotorParameters current = baseline;
  result.baseline_predictions = predict({current})[0];
  result.baseline_map = map_disagreement(set, result.baseline_predictions, model);
  Predictions current_predictions = result.baseline_predictions;
  std::vector<double> current_r = model.residuals(current_predictions);

  std::vector<bool> used(candidates.size(), false);
  while (static_cast<int>(result.effects.size()) < options.max_effects) {
    DiscrepancyRound round;
    const double sse0 = sum_of_squares(current_r, train);
    // Screening: a probe at the typical magnitude, then Gauss-Newton / secant steps, every
    // candidate of a step in one parallel batch.
    std::vector<std::size_t> active;
    std::vector<Screened> best(candidates.size());
    std::vector<Screened> last(candidates.size());
    std::vector<Screened> previous(candidates.size());
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      CandidateScore score;
      score.name = std::string(candidates[c]->name);
      if (used[c] || effect_enabled(current, *candidates[c])) {
        score.skipped = true;
        score.note = "already in the model";
      } else if (candidates[c]->needs_time && !set.has_time) {
        score.skipped = true;
        score.note = "needs time_s (builds up over a session)";
      } else {
        active.push_back(c);
        best[c] = {0.0, sse0, current_predictions, current_r};
        previous[c] = best[c];
      }
      round.candidates.push_back(score);
    }
    std::vector<double> thetas(candidates.size(), 1.0);
    for (int step = 0; step <= options.screening_steps && !active.empty(); ++step) {
      std::vector<MotorParameters> models;
      for (std::size_t c : active) {
        MotorParameters p = current;
        enable_effect(p, *candidates[c], candidates[c]->neutral + thetas[c] * candidates[c]->typical);
        models.push_back(p);
      }
      const std::vector<Predictions> batch = predict(models);
      std::vector<std::pair<double, std::size_t>> promising;  // (predicted SSE, candidate)
      for (std::size_t a = 0; a < active.size(); ++a) {
        const std::size_t c = active[a];
        const CandidateEffect& e = *candidates[c];
        Screened s{thetas[c], 0.0, batch[a], model.residuals(batch[a])};
        s.sse = sum_of_squares(s.residuals, train);
        if (s.sse < best[c].sse) best[c] = s;
        // Secant through the last two evaluations (the first: the current model at theta 0).
        const Screened& from = step == 0 ? previous[c] : last[c];
        const double dtheta = s.theta - from.theta;
        double jr = 0.0, jj = 0.0;
        for (std::size_t k : train) {
          const double j = (s.residuals[k] - from.residuals[k]) / dtheta;
          jr += j * s.residuals[k];
          jj += j * j;
        }
        double lo = (e.lower - e.neutral) / e.typical;
        double hi = (e.upper - e.neutral) / e.typical;
        if (lo > hi) std::swap(lo, hi);
        double next = jj > 0.0 ? s.theta - jr / jj : s.theta;
        next = std::clamp(next, lo, hi);
        if (std::abs(next - s.theta) < 1e-3) next = s.theta + 1e-3;
        thetas[c] = next;
        // Gauss-Newton prediction of the minimum: screening goes on only for candidates that
        // could pass the BIC margin, at most the three best.
        const double predicted = std::min(best[c].sse, jj > 0.0 ? s.sse - jr * jr / jj : s.sse);
        if (delta_bic(predicted, sse0, n, 1) < -options.bic_margin) promising.emplace_back(predicted, c);
        last[c] = std::move(s);
      }
      std::sort(promising.begin(), promising.end());
      if (promising.size() > 3) promising.resize(3);
      active.clear();
      for (const auto& p : promising) active.push_back(p.second);
    }
    active.clear();
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      if (!round.candidates[c].skipped) active.push_back(c);
    }
    std::optional<std::size_t> winner;
    for (std::size_t c : active) {
      CandidateScore& score = round.candidates[c];
      score.value = candidates[c]->neutral + best[c].theta * candidates[c]->typical;
      score.train_rms = std::sqrt(best[c].sse / static_cast<double>(std::max<std::size_t>(n, 1)));
      score.held_out_rms = rms(best[c].residuals, test);
      score.delta_bic = delta_bic(best[c].sse, sse0, n, 1);
      if (!winner || best[c].sse < best[*winner].sse) winner = c;
    }
    if (!winner || round.candidates[*winner].delta_bic > -options.bic_margin) {
      round.verdict = winner ? "no candidate lowers the BIC by more than " +
                                   format("%.3g", options.bic_margin) + " (best: " +
                                   round.candidates[*winner].name + ", " +
                                   format("%+.3g", round.candidates[*winner].delta_bic) + ")"
                             : "no candidate left";
      result.rounds.push_back(round);
      break;
    }
    // Full fit of the best screened candidate, jointly with the effects named before it. From
    // the second round on, an earlier fit may have absorbed part of the new effect, which can
    // misrank the screening: the three best screened candidates are fitted and the one with
    // the lowest BIC among those passing both tests is named.
    std::vector<std::size_t> ranked;
    for (std::size_t k : active) {
      if (round.candidates[k].delta_bic < -options.bic_margin) ranked.push_back(k);
    }
    std::sort(ranked.begin(), ranked.end(), [&](std::size_t x, std::size_t y) { return best[x].sse < best[y].sse; });
    ranked.resize(std::min<std::size_t>(ranked.size(), result.effects.empty() ? 1 : 3));
    struct Trial {
      std::size_t c;
      EffectFit fit;
      std::vector<double> residuals;
      double bic, t;
      bool passes;
    };
    std::optional<Trial> chosen;
    std::vector<const CandidateEffect*> fitted_effects;
    for (const NamedEffect& named : result.effects) fitted_effects.push_back(find_candidate_effect(named.name));
    fitted_effects.push_back(nullptr);
    const std::size_t last_index = fitted_effects.size() - 1;
    for (std::size_t c : ranked) {
      std::vector<double> start;
      for (const NamedEffect& named : result.effects) start.push_back(named.value);
      start.push_back(round.candidates[c].value);
      fitted_effects[last_index] = candidates[c];
      const EffectEvaluator eval(current, fitted_effects, set, options.prediction, parallel,
                                 result.model_evaluations);
      Trial trial{c, fit_effect(eval, model, train, start, options.max_fit_iterations, &best[c].predictions), {}, 0.0, 0.0, false};
      trial.residuals = model.residuals(trial.fit.predictions);
      trial.bic = delta_bic(trial.fit.train_sum_of_squares, sse0, n, 1);
      trial.t = held_out_t(current_r, trial.residuals, test);
      trial.passes = trial.fit.ok && trial.bic < -options.bic_margin && trial.t > options.held_out_t;
      CandidateScore& score = round.candidates[c];
      score.value = trial.fit.values[last_index];
      score.train_rms = std::sqrt(trial.fit.train_sum_of_squares / static_cast<double>(n));
      score.held_out_rms = rms(trial.residuals, test);
      score.delta_bic = trial.bic;
      const bool better = !chosen || (trial.passes && !chosen->passes) ||
                          (trial.passes == chosen->passes && trial.bic < chosen->bic);
      if (better) chosen = std::move(trial);
    }
    const std::size_t c = chosen->c;
    const CandidateEffect& e = *candidates[c];
    const EffectFit& fit = chosen->fit;
    const std::vector<double>& fit_r = chosen->residuals;
    const double bic = chosen->bic;
    const double t = chosen->t;
    fitted_effects[last_index] = &e;
    const EffectEvaluator eval(current, fitted_effects, set, options.prediction, parallel,
                               result.model_evaluations);
    round.fitted = c;
    round.accepted = chosen->passes;
    if (!round.accepted) {
      round.verdict = std::string(e.name) + " fitted but not named: " +
                      format("delta BIC %+.3g, held-out t %.3g", bic, t);
      result.rounds.push_back(round);
      break;
    }
    NamedEffect named;
    named.name = std::string(e.name);
    named.key = std::string(e.free_key);
    named.unit = std::string(effect_free_spec(e).unit);
    named.value = fit.values[last_index];
    named.standard_error = fit.standard_errors[last_index];
    named.delta_bic = bic;
    named.held_out_t = t;
    named.held_out_rms_before = rms(current_r, test);
    named.held_out_rms_after = rms(fit_r, test);
    round.verdict = "named " + named.name;
    for (std::size_t k = 0; k < result.effects.size(); ++k) {  // refined jointly
      result.effects[k].value = fit.values[k];
      result.effects[k].standard_error = fit.standard_errors[k];
    }
    result.effects.push_back(named);
    result.rounds.push_back(round);
    used[c] = true;
    current = eval.parameters_at(fit.values);
    current_predictions = fit.predictions;
    current_r = fit_r;
  }

  result.augmented = current;
  result.augmented_predictions = current_predictions;
  result.augmented_map = map_disagreement(set, current_predictions, model);
  const std::vector<double> r0 = model.residuals(result.baseline_predictions);
  result.rms_before = rms(r0, test);
  result.rms_after = rms(current_r, test);
  for (std::size_t k : test) {
    QuantityGap& g = result.gaps[static_cast<std::size_t>(model.slots()[k].quantity)];
    ++g.count;
    g.rms_before += r0[k] * r0[k];
    g.rms_after += current_r[k] * current_r[k];
    g.max_before = std::max(g.max_before, std::abs(r0[k]));
    g.max_after = std::max(g.max_after, std::abs(current_r[k]));
  }
  for (QuantityGap& g : result.gaps) {
    if (g.count == 0) continue;
    g.rms_before = std::sqrt(g.rms_before / g.count);
    g.rms_after = std::sqrt(g.rms_after / g.count);
  }
  if (result.effects.empty()) {
    result.conclusion = result.baseline_map.structured
                            ? "no candidate explains the residual; unexplained residual, " +
                                  result.baseline_map.summary
                            : "no significant missing effect: the residual is " +
                                  result.baseline_map.summary;
  } else {
    result.conclusion = "named";
    for (const NamedEffect& e : result.effects) result.conclusion += " " + e.name;
    result.conclusion += "; held-out RMS " + format("%.3g %% -> %.3g %%", 100.0 * result.rms_before,
                                                    100.0 * result.rms_after);
    result.conclusion += "; remaining residual " + result.augmented_map.summary;
  }
  return result;
}

}  // namespace swum
