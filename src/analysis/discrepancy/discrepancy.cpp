#include "analysis/discrepancy/discrepancy.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <stdexcept>
#include <tuple>

#include "analysis/discrepancy/candidate_fitting.h"
#include "formats/number_format.h"

namespace swum {
namespace {

std::string join_names(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::vector<FreeParameter> free_parameters_of(const std::vector<const CandidateEffect*>& effects) {
  std::vector<FreeParameter> free;
  for (const CandidateEffect* e : effects) free.push_back(effect_free_parameter(*e));
  return free;
}

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
        throw std::invalid_argument("unknown effect '" + name + "' (known: " + candidate_effect_names() + ")");
      }
      candidates.push_back(e);
    }
  }
  if (options.discovery.enabled) validate_discovery_groups(options.discovery, baseline);
  DiscrepancyResult result;
  result.held_out = held_out_rows(set, {options.held_out_fraction, options.min_held_out_points, options.split_seed},
                                  result.held_out_points, result.operating_points);
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

  const bool robust_fit = options.robust;
  std::vector<bool> used(candidates.size(), false);
  // The library's rounds on top of `current`: each names at most one effect (run again after a
  // change of the base model is accepted, for effects beside it).
  auto library_rounds = [&](bool after_change) {
    std::fill(used.begin(), used.end(), false);
    // On the changed model the effects the change replaced are not candidates again: that
    // question ("the effect beside the change") was the step's to answer.
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      for (const NamedEffect& e : result.superseded) used[c] = used[c] || e.name == candidates[c]->name;
    }
    while (static_cast<int>(result.effects.size()) < options.max_effects) {
      DiscrepancyRound round;
      round.after_change = after_change;
      const double sse0 = sum_of_squares(current_r, train);
      // Candidates are screened, ranked and first fitted by the Cauchy cost at a scale set by
      // what the current model leaves: a few readings on the other side of a fold or a dead-zone
      // edge (residuals of 100 % and more) must not choose the effect.
      const double round_scale = kCauchyEfficiencyScale * robust_sigma(current_r, train);
      // Screening: a probe at the typical magnitude, then Gauss-Newton / secant steps, every
      // candidate of a step in one parallel batch (candidate_fitting.h).
      std::vector<std::optional<FreeParameter>> screened_free(candidates.size());
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
          screened_free[c] = effect_free_parameter(*candidates[c]);
        }
        round.candidates.push_back(score);
      }
      const std::vector<Screened> best = screen_candidates(
          current, screened_free, current_predictions, current_r, model, train,
          {options.screening_steps, options.bic_margin, round_scale, {}, 3}, predict);
      std::vector<std::size_t> active;
      for (std::size_t c = 0; c < candidates.size(); ++c) {
        if (!round.candidates[c].skipped) active.push_back(c);
      }
      // The winner: the lowest robust cost among the candidates that pass the BIC margin; when
      // none does, the lowest BIC (for the verdict).
      std::optional<std::size_t> winner;
      for (std::size_t c : active) {
        CandidateScore& score = round.candidates[c];
        score.value = candidates[c]->neutral + best[c].theta * candidates[c]->typical;
        score.train_rms = std::sqrt(best[c].sse / static_cast<double>(std::max<std::size_t>(n, 1)));
        score.held_out_rms = rms_of(best[c].residuals, test);
        score.delta_bic = delta_bic(best[c].sse, sse0, n, 1);
      }
      for (std::size_t c : active) {
        const bool passes = round.candidates[c].delta_bic < -options.bic_margin;
        const bool winner_passes = winner && round.candidates[*winner].delta_bic < -options.bic_margin;
        if (!winner || (passes && !winner_passes) || (passes && best[c].robust < best[*winner].robust) ||
            (!passes && !winner_passes && round.candidates[c].delta_bic < round.candidates[*winner].delta_bic)) {
          winner = c;
        }
      }
      if (!winner || round.candidates[*winner].delta_bic > -options.bic_margin) {
        round.verdict = winner
                            ? "no candidate lowers the BIC by more than " + format_numbers("%.3g", options.bic_margin) +
                                  " (best: " + round.candidates[*winner].name + ", " +
                                  format_numbers("%+.3g", round.candidates[*winner].delta_bic) + ")"
                            : "no candidate left";
        result.rounds.push_back(round);
        break;
      }
      // Full fit of the best screened candidate, jointly with the effects named before it. From
      // the second round on, an earlier fit may have absorbed part of the new effect, which can
      // misrank the screening: the three best screened candidates are fitted, the one with the
      // lowest training BIC is chosen, and only that one is tested on the held-out points.
      std::vector<std::size_t> ranked;
      for (std::size_t k : active) {
        if (round.candidates[k].delta_bic < -options.bic_margin) ranked.push_back(k);
      }
      std::sort(ranked.begin(), ranked.end(),
                [&](std::size_t x, std::size_t y) { return best[x].robust < best[y].robust; });
      ranked.resize(std::min<std::size_t>(ranked.size(), result.effects.empty() ? 1 : 3));
      struct Trial {
        std::size_t c;
        ParameterFit fit;
        std::vector<double> residuals;
        double bic;
        HeldOutEvidence evidence;
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
        const ParameterEvaluator eval(current, free_parameters_of(fitted_effects), set, options.prediction, parallel,
                                      result.model_evaluations);
        Trial trial{
            c,
            fit_candidate(eval, model, train, start, &best[c].predictions, round_scale, robust_fit, options.max_fit_iterations),
            {},
            0.0,
            {},
            false};
        trial.residuals = model.residuals(trial.fit.predictions);
        trial.bic = delta_bic(trial.fit.train_sum_of_squares, sse0, n, 1);

        CandidateScore& score = round.candidates[c];
        score.value = trial.fit.values[last_index];
        score.train_rms = std::sqrt(trial.fit.train_sum_of_squares / static_cast<double>(n));
        score.held_out_rms = rms_of(trial.residuals, test);
        score.delta_bic = trial.bic;
        // Chosen on the training points alone (the lowest BIC of a usable fit); only the chosen
        // one is tested on the held-out points, so their test is not spent on the choice.
        const bool better = !chosen || (trial.fit.ok && !chosen->fit.ok) ||
                            (trial.fit.ok == chosen->fit.ok && trial.bic < chosen->bic);
        if (better) chosen = std::move(trial);
      }
      if (!chosen) {  // nothing ranked (a delta BIC exactly at the margin, or not a number)
        round.verdict = "no candidate lowers the BIC by more than " + format_numbers("%.3g", options.bic_margin);
        result.rounds.push_back(round);
        break;
      }
      chosen->evidence = compare_held_out(set, model, current_r, chosen->residuals, test, options.split_seed);
      chosen->passes = chosen->fit.ok && chosen->bic < -options.bic_margin &&
                       chosen->evidence.p_value < options.significance;
      const std::size_t c = chosen->c;
      const CandidateEffect& e = *candidates[c];
      const ParameterFit& fit = chosen->fit;
      const std::vector<double>& fit_r = chosen->residuals;
      const double bic = chosen->bic;
      const HeldOutEvidence& evidence = chosen->evidence;
      fitted_effects[last_index] = &e;
      const ParameterEvaluator eval(current, free_parameters_of(fitted_effects), set, options.prediction, parallel,
                                    result.model_evaluations);
      round.fitted = c;
      round.accepted = chosen->passes;
      round.held_out = evidence;
      round.fitted_delta_bic = bic;
      if (!round.accepted) {
        std::string why;
        if (!fit.ok) why = "the fit did not converge to a usable solution; ";
        if (!(bic < -options.bic_margin)) {
          why += format_numbers("delta BIC %+.3g is not below -%.3g; ", bic, options.bic_margin);
        }
        if (!(evidence.p_value < options.significance)) {
          why += format_numbers("held-out p = %.3g is not below %.3g", evidence.p_value, options.significance) +
                 format_numbers(" (signed-rank %.3g, sign-flip %.3g; ", evidence.signed_rank_p, evidence.sign_flip_p) +
                 std::to_string(evidence.improved) + " of " + std::to_string(evidence.points) +
                 " held-out points better)";
        }
        if (why.size() >= 2 && why.compare(why.size() - 2, 2, "; ") == 0) why.resize(why.size() - 2);
        round.verdict = std::string(e.name) + " fitted but not named: " + why +
                        format_numbers("; held-out RMS %.3g %% -> %.3g %%", 100.0 * evidence.rms_before,
                                       100.0 * evidence.rms_after);
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
      named.held_out = evidence;
      round.verdict = "named " + named.name + ": " + describe_evidence(bic, evidence);
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
  };
  library_rounds(false);

  // Discovery: a change of the base model, alone, beside the library's effects or instead of
  // them (discovery.h). Not when nothing was named and the baseline's residual is within the
  // noise on the training rows: there is nothing for a change to explain (the conclusion says
  // so), and noise-only sessions stay as cheap as before. (Training rows only: the held-out rows
  // must not choose the hypothesis they then test.)
  if (options.discovery.enabled) {
    std::vector<std::size_t> train_rows;
    for (std::size_t row = 0; row < result.held_out.size(); ++row) {
      if (!result.held_out[row]) train_rows.push_back(row);
    }
    const bool nothing_to_explain = result.effects.empty() &&
                                    !map_disagreement(set, result.baseline_predictions, model, train_rows).structured;
    if (nothing_to_explain) {
      result.discovery.outcome = DiscoveryOutcome::nothing_to_explain;
      result.discovery.significance = options.significance;
      result.discovery.verdict = "not run: nothing named and the baseline's residual is within the noise";
    } else {
      DiscoveryStart start{&baseline, &result.baseline_predictions, &current, &current_predictions, {}, {}, false};
      for (const NamedEffect& e : result.effects) {
        start.library_effects.push_back(e.name);
        start.library_values.push_back(e.value);
      }
      start.library_explains = !result.effects.empty() &&
                               !map_disagreement(set, current_predictions, model, train_rows).structured;
      const DiscoverySettings settings{options.discovery,  options.bic_margin,         options.significance,
                                       options.robust,     options.max_fit_iterations, options.screening_steps,
                                       options.split_seed, options.prediction};
      result.discovery = run_discovery(start, set, model, train, test, settings, parallel, result.model_evaluations);
      const Discovery& d = result.discovery;
      const GroupFit* accepted = accepted_change(d);
      if (d.outcome == DiscoveryOutcome::with_library) {
        for (std::size_t k = 0; k < result.effects.size(); ++k) {  // refined jointly
          result.effects[k].value = accepted->effect_values[k];
          result.effects[k].standard_error = accepted->effect_standard_errors[k];
        }
      }
      if (d.outcome == DiscoveryOutcome::instead_of_library) {
        result.superseded = std::move(result.effects);
        result.effects.clear();
      }
      if (accepted != nullptr) {
        current = accepted->parameters;
        current_predictions = accepted->predictions;
        current_r = accepted->residuals;
      }
      // A change alone (or instead of the library's effects) may leave room for an effect beside
      // it: the library's rounds again, on the changed model.
      if (d.outcome == DiscoveryOutcome::alone || d.outcome == DiscoveryOutcome::instead_of_library) {
        library_rounds(true);
        // Effects named beside the change: the change and they, refitted jointly from the
        // baseline, so that no value in the report is from a fit that held another one fixed.
        if (!result.effects.empty()) {
          std::vector<std::string> names;
          std::vector<double> values;
          for (const NamedEffect& e : result.effects) {
            names.push_back(e.name);
            values.push_back(e.value);
          }
          GroupFit joint = refit_change_with_effects(*accepted, names, values, baseline, result.baseline_predictions,
                                                     set, model, train, test, settings, parallel,
                                                     result.model_evaluations);
          // A pair whose one group the effects have made unnecessary (its change within two
          // standard errors of none): the smaller change, refitted with the effects.
          if (joint.ok && joint.groups.size() == 2) {
            for (std::size_t k = 0; k < 2; ++k) {
              const double none = find_parameter_group(joint.groups[k])->change == GroupChange::shift ? 0.0 : 1.0;
              if (!(std::abs(joint.values[k] - none) < 2.0 * joint.standard_errors[k])) continue;
              GroupFit smaller;  // refit_change_with_effects reads the groups and their values
              smaller.groups = {joint.groups[1 - k]};
              smaller.values = {joint.values[1 - k]};
              GroupFit refit = refit_change_with_effects(smaller, names, joint.effect_values, baseline,
                                                         result.baseline_predictions, set, model, train, test, settings,
                                                         parallel, result.model_evaluations);
              if (refit.ok) joint = std::move(refit);
              break;
            }
          }
          if (joint.ok) {
            for (std::size_t k = 0; k < result.effects.size(); ++k) {
              result.effects[k].value = joint.effect_values[k];
              result.effects[k].standard_error = joint.effect_standard_errors[k];
            }
            current = joint.parameters;
            current_predictions = joint.predictions;
            current_r = joint.residuals;
            Discovery& dm = result.discovery;
            dm.verdict += "; beside it the library's rounds on the changed model named " + join_names(names) +
                          ", refitted jointly: " + describe_group_fit(joint);
            dm.with_library_fits.insert(dm.with_library_fits.begin(), std::move(joint));
            dm.effects_after_change = true;
          }
        }
      }
    }
  }

  result.augmented = current;
  result.augmented_predictions = current_predictions;
  result.augmented_map = map_disagreement(set, current_predictions, model);
  const std::vector<double> r0 = model.residuals(result.baseline_predictions);
  result.rms_before = rms_of(r0, test);
  result.rms_after = rms_of(current_r, test);
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
  const DiscoveryOutcome outcome = result.discovery.outcome;
  if (outcome == DiscoveryOutcome::alone || outcome == DiscoveryOutcome::instead_of_library ||
      outcome == DiscoveryOutcome::with_library) {
    result.conclusion = result.effects.empty() ? "" : "named";
    for (const NamedEffect& e : result.effects) result.conclusion += " " + e.name;
    if (!result.effects.empty()) result.conclusion += "; ";
    result.conclusion += result.discovery.verdict;
    result.conclusion += format_numbers(" (noise %.3g %%)", 100.0 * result.augmented_map.noise);
    result.conclusion += "; remaining residual " + result.augmented_map.summary;
  } else if (result.effects.empty()) {
    if (!result.rounds.empty() && result.rounds.back().fitted && result.rounds.back().held_out.reduction > 0.0) {
      const DiscrepancyRound& last = result.rounds.back();
      // A fit that helped but did not pass: say so rather than "nothing explains it".
      result.conclusion = "nothing named: " + last.verdict;
      if (outcome == DiscoveryOutcome::nothing && result.discovery.held_out.reduction > 0.0) {
        result.conclusion += "; " + result.discovery.verdict;
      }
      result.conclusion += "; baseline residual " + result.baseline_map.summary;
    } else if (outcome == DiscoveryOutcome::nothing && result.discovery.held_out.reduction > 0.0) {
      // No prepared effect, and the best change of the base model helped but did not pass.
      result.conclusion = "nothing named: no prepared effect explains the residual; " + result.discovery.verdict +
                          "; baseline residual " + result.baseline_map.summary;
    } else {
      result.conclusion = result.baseline_map.structured
                              ? "no candidate explains the residual; unexplained residual, " +
                                    result.baseline_map.summary
                              : "no significant missing effect: the residual is " + result.baseline_map.summary;
    }
  } else {
    result.conclusion = "named";
    for (const NamedEffect& e : result.effects) result.conclusion += " " + e.name;
    result.conclusion += "; held-out RMS " +
                         format_numbers("%.3g %% -> %.3g %%", 100.0 * result.rms_before, 100.0 * result.rms_after);
    result.conclusion += "; remaining residual " + result.augmented_map.summary;
    if (outcome == DiscoveryOutcome::library_stands && !result.discovery.indistinguishable.empty()) {
      result.conclusion += "; " + result.discovery.verdict;
    }
  }
  return result;
}

}  // namespace swum
