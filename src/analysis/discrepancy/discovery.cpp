#include "analysis/discrepancy/discovery.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "analysis/discrepancy/candidate_effects.h"
#include "analysis/discrepancy/candidate_fitting.h"
#include "analysis/discrepancy/parameter_groups.h"
#include "formats/number_format.h"

namespace swum {
namespace {

std::string evidence_text(const HeldOutEvidence& e) {
  return std::to_string(e.improved) + " of " + std::to_string(e.points) +
         format_numbers(" held-out points better, p = %.2g", e.p_value) +
         format_numbers("; held-out RMS %.3g %% -> %.3g %%", 100.0 * e.rms_before, 100.0 * e.rms_after);
}

// The groups to search, with their free parameters around the baseline.
struct Group {
  const ParameterGroup* group;
  FreeParameter free;
};

std::vector<Group> groups_for(const MotorParameters& baseline, const DiscoveryOptions& options,
                              std::vector<GroupScreening>& screened) {
  std::vector<const ParameterGroup*> wanted;
  if (options.groups.empty()) {
    for (const ParameterGroup& g : parameter_groups()) wanted.push_back(&g);
  } else {
    for (const std::string& name : options.groups) {
      const ParameterGroup* g = find_parameter_group(name);
      if (g == nullptr) {
        throw std::invalid_argument("unknown group '" + name + "' (known: " + parameter_group_names() + ")");
      }
      if (group_parameters(*g, baseline).empty()) (void)group_free_parameter(*g, baseline);  // throws why
      wanted.push_back(g);
    }
  }
  std::vector<Group> out;
  for (const ParameterGroup* g : wanted) {
    GroupScreening s;
    s.name = std::string(g->name);
    if (group_parameters(*g, baseline).empty()) {
      s.note = g->change == GroupChange::shift ? "the natural frequencies are not parameters of this config"
                                               : "its parameters are 0 in this config";
    } else {
      out.push_back({g, group_free_parameter(*g, baseline)});
    }
    screened.push_back(s);
  }
  return out;
}

bool near_bound(const FreeParameter& f, double value) {
  const double tolerance = 1e-3 * std::abs(f.scale);
  return std::abs(value - f.lower) < tolerance || std::abs(value - f.upper) < tolerance;
}

}  // namespace

std::string describe_group_fit(const GroupFit& fit) {
  std::string out;
  for (std::size_t k = 0; k < fit.groups.size(); ++k) {
    const ParameterGroup* g = find_parameter_group(fit.groups[k]);
    if (!out.empty()) out += " and ";
    out += fit.groups[k] + " " + describe_group_change(*g, fit.values[k]);
    out += std::isfinite(fit.standard_errors[k]) ? format_numbers(" +- %.2g", fit.standard_errors[k])
                                                 : std::string(" (standard error unknown)");
    if (g->change == GroupChange::shift) out += " " + fit.units[k];
    out += " (";
    for (std::size_t s = 0; s < fit.keys[k].size(); ++s) out += (s == 0 ? "" : ", ") + fit.keys[k][s];
    out += fit.keys[k].size() > 1 ? " together)" : ")";
    if (fit.at_bound[k]) out += " [at its bound: the data push it further]";
  }
  return out;
}

Discovery run_discovery(const DiscoveryStart& start, const MeasurementSet& set, const ResidualModel& model,
                        std::span<const std::size_t> train, std::span<const std::size_t> test,
                        const DiscoverySettings& settings, const ParallelFor& parallel, int& evaluation_counter) {
  Discovery d;
  if (!settings.options.enabled) return d;
  const MotorParameters& baseline = *start.baseline;
  const std::vector<Group> groups = groups_for(baseline, settings.options, d.screened);
  if (groups.empty()) {
    d.verdict = "no group of base parameters applies to this config";
    return d;
  }
  const std::size_t n = train.size();
  const std::vector<double> base_r = model.residuals(*start.baseline_predictions);
  const std::vector<double> library_r = model.residuals(*start.library_predictions);
  const double sse0 = sum_of_squares(base_r, train);
  const int library_count = static_cast<int>(start.library_effects.size());
  d.library_delta_bic = library_count == 0 ? 0.0 : delta_bic(sum_of_squares(library_r, train), sse0, n, library_count);
  auto predict = [&](const std::vector<MotorParameters>& models) {
    evaluation_counter += static_cast<int>(models.size());
    return predict_points(models, set.rows, settings.prediction, parallel);
  };

  // 1. Screening of every group on the baseline, the library's own steps.
  const double round_scale = kCauchyEfficiencyScale * robust_sigma(base_r, train);
  // Each group is probed in both directions (a factor above and below 1, a shift up and down):
  // unlike an effect, a change of the base model has no sign known in advance, and where a
  // change moves the fold a step the wrong way can leave the secant nowhere to go. The better
  // side is kept.
  std::vector<std::optional<FreeParameter>> free;
  for (const Group& g : groups) {
    free.emplace_back(g.free);
    FreeParameter down = g.free;
    down.scale = -g.free.scale;
    free.emplace_back(down);
  }
  const std::vector<Screened> both = screen_candidates(baseline, free, *start.baseline_predictions, base_r, model,
                                                       train,
                                                       {settings.screening_steps, settings.bic_margin, round_scale},
                                                       predict);
  std::vector<Screened> screened;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    Screened up = both[2 * g];
    Screened down = both[2 * g + 1];
    down.theta = -down.theta;  // in the group's own direction
    screened.push_back(down.robust < up.robust ? std::move(down) : std::move(up));
  }
  std::vector<std::size_t> order;  // groups by screened robust cost
  for (std::size_t g = 0; g < groups.size(); ++g) {
    order.push_back(g);
    for (GroupScreening& s : d.screened) {
      if (s.name != groups[g].group->name) continue;
      s.value = groups[g].free.origin + screened[g].theta * groups[g].free.scale;
      s.delta_bic = delta_bic(screened[g].sse, sse0, n, 1);
    }
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return screened[a].robust < screened[b].robust; });

  // 2. Full fits: each of the best screened groups that could pass the margin, alone.
  auto fit_change = [&](const std::vector<std::size_t>& members, std::vector<double> start_values,
                        const Predictions* start_predictions, bool with_library) {
    std::vector<FreeParameter> parameters;
    const MotorParameters& origin = with_library ? *start.library : baseline;
    if (with_library) {
      for (std::size_t k = 0; k < start.library_effects.size(); ++k) {
        parameters.push_back(effect_free_parameter(*find_candidate_effect(start.library_effects[k])));
      }
    }
    for (std::size_t m : members) parameters.push_back(groups[m].free);
    const ParameterEvaluator eval(origin, parameters, set, settings.prediction, parallel, evaluation_counter);
    const ParameterFit fit = fit_candidate(eval, model, train, start_values, start_predictions, round_scale,
                                           settings.robust, settings.max_fit_iterations);
    GroupFit out;
    const std::size_t first = with_library ? start.library_effects.size() : 0;
    for (std::size_t k = 0; k < first; ++k) {
      out.effect_values.push_back(fit.values[k]);
      out.effect_standard_errors.push_back(fit.standard_errors[k]);
    }
    for (std::size_t k = 0; k < members.size(); ++k) {
      const FreeParameter& f = groups[members[k]].free;
      out.groups.emplace_back(groups[members[k]].group->name);
      out.units.push_back(f.unit);
      std::vector<std::string> keys;
      for (const ParameterSpec* spec : group_parameters(*groups[members[k]].group, baseline)) {
        keys.push_back(spec->name());
      }
      out.keys.push_back(std::move(keys));
      out.values.push_back(fit.values[first + k]);
      out.standard_errors.push_back(fit.standard_errors[first + k]);
      out.at_bound.push_back(near_bound(f, fit.values[first + k]));
    }
    out.ok = fit.ok;
    out.residuals = model.residuals(fit.predictions);
    out.delta_bic = delta_bic(fit.train_sum_of_squares, sse0, n, static_cast<int>(parameters.size()));
    out.train_rms = std::sqrt(fit.train_sum_of_squares / static_cast<double>(std::max<std::size_t>(n, 1)));
    out.held_out_rms = rms_of(out.residuals, test);
    out.parameters = eval.parameters_at(fit.values);
    out.predictions = fit.predictions;
    return out;
  };
  std::vector<std::size_t> single_members;
  for (std::size_t g : order) {
    if (static_cast<int>(single_members.size()) >= settings.options.fitted_singles) break;
    const double screened_bic = delta_bic(screened[g].sse, sse0, n, 1);
    if (screened_bic < -settings.bic_margin &&
        (!start.library_explains || screened_bic < d.library_delta_bic + settings.bic_margin)) {
      single_members.push_back(g);
    }
  }
  if (single_members.empty()) {
    const std::size_t best = order.front();
    const std::string best_text = " (best: " + std::string(groups[best].group->name) +
                                  format_numbers(", delta BIC %+.4g against the baseline",
                                                 delta_bic(screened[best].sse, sse0, n, 1));
    if (library_count > 0) {
      d.outcome = DiscoveryOutcome::library_stands;
      std::string names;
      for (const std::string& e : start.library_effects) names += (names.empty() ? "" : ", ") + e;
      d.verdict = names + " stands: no change of the base model comes within the BIC margin of it" + best_text +
                  format_numbers(", the library's effects %+.4g)", d.library_delta_bic);
      return d;
    }
    d.outcome = DiscoveryOutcome::nothing;
    d.verdict = "no group of base parameters lowers the BIC by more than " +
                format_numbers("%.3g", settings.bic_margin) + best_text + ")";
    return d;
  }
  for (std::size_t g : single_members) {
    d.fits.push_back(fit_change({g}, {groups[g].free.origin + screened[g].theta * groups[g].free.scale},
                                &screened[g].predictions, false));
  }
  auto by_bic = [](const GroupFit& a, const GroupFit& b) { return a.ok != b.ok ? a.ok : a.delta_bic < b.delta_bic; };
  std::stable_sort(d.fits.begin(), d.fits.end(), by_bic);
  // 3. Pairs of the three best screened groups, when the best single change leaves a structured
  // residual (a second change is asked for by the data, not tried on every session).
  const GroupFit& best_single = d.fits.front();
  if (settings.options.pairs && !start.library_explains && groups.size() >= 2 &&
      map_disagreement(set, best_single.predictions, model).structured) {
    const std::size_t top = std::min<std::size_t>(3, order.size());
    auto value_of = [&](std::size_t g) {
      for (const GroupFit& f : d.fits) {
        if (f.groups.size() == 1 && f.groups[0] == groups[g].group->name) return f.values[0];
      }
      return groups[g].free.origin + screened[g].theta * groups[g].free.scale;
    };
    for (std::size_t a = 0; a < top; ++a) {
      for (std::size_t b = a + 1; b < top; ++b) {
        d.fits.push_back(fit_change({order[a], order[b]}, {value_of(order[a]), value_of(order[b])}, nullptr, false));
      }
    }
    std::stable_sort(d.fits.begin(), d.fits.end(), by_bic);
  }
  // The chosen change: the lowest BIC, but a pair only when it beats every single change by the
  // margin (the smallest change that explains the data).
  std::optional<std::size_t> chosen;
  for (std::size_t k = 0; k < d.fits.size(); ++k) {
    if (!d.fits[k].ok) continue;
    if (!chosen) {
      chosen = k;
      continue;
    }
    const GroupFit& c = d.fits[*chosen];
    const GroupFit& f = d.fits[k];
    if (f.groups.size() < c.groups.size() && f.delta_bic < c.delta_bic + settings.bic_margin) chosen = k;
  }
  if (!chosen) {
    d.outcome = library_count > 0 ? DiscoveryOutcome::library_stands : DiscoveryOutcome::nothing;
    d.verdict = "no fit of a group of base parameters converged to a usable solution";
    return d;
  }
  const GroupFit& g = d.fits[*chosen];
  auto mark_indistinguishable = [&](double reference, std::optional<std::size_t> except) {
    for (std::size_t k = 0; k < d.fits.size(); ++k) {
      if (except && k == *except) continue;
      const GroupFit& f = d.fits[k];
      if (!f.ok || std::abs(f.delta_bic - reference) > settings.bic_margin) continue;
      // A pair that contains the chosen change and adds nothing is not an alternative.
      if (except && f.groups.size() > d.fits[*except].groups.size() &&
          std::find(f.groups.begin(), f.groups.end(), d.fits[*except].groups[0]) != f.groups.end()) {
        continue;
      }
      d.indistinguishable.push_back(k);
    }
  };
  const std::string change = describe_group_fit(g);

  // 4. Against the library: alone, with its effects, instead of them, or not at all.
  if (library_count == 0) {
    d.held_out = compare_held_out(set, model, base_r, g.residuals, test, settings.split_seed);
    const bool passes = g.delta_bic < -settings.bic_margin && d.held_out.p_value < settings.significance;
    d.outcome = passes ? DiscoveryOutcome::alone : DiscoveryOutcome::nothing;
    if (passes) {
      d.chosen = chosen;
      mark_indistinguishable(g.delta_bic, chosen);
      d.verdict = "not in the library: " + change + format_numbers("; delta BIC %+.4g; ", g.delta_bic) +
                  evidence_text(d.held_out);
    } else {
      d.verdict = "best change of the base model " + change + " not named: " +
                  (g.delta_bic < -settings.bic_margin
                       ? format_numbers("held-out p = %.3g is not below ", d.held_out.p_value) +
                             format_numbers("%.3g", settings.significance)
                       : format_numbers("delta BIC %+.3g is not below -", g.delta_bic) +
                             format_numbers("%.3g", settings.bic_margin)) +
                  format_numbers("; held-out RMS %.3g %% -> %.3g %%", 100.0 * d.held_out.rms_before,
                                 100.0 * d.held_out.rms_after);
    }
    return d;
  }
  std::vector<std::size_t> members;
  for (const std::string& name : g.groups) {
    for (std::size_t k = 0; k < groups.size(); ++k) {
      if (groups[k].group->name == name) members.push_back(k);
    }
  }
  std::vector<double> joint_start = start.library_values;
  joint_start.insert(joint_start.end(), g.values.begin(), g.values.end());
  std::string library_names;
  for (const std::string& e : start.library_effects) library_names += (library_names.empty() ? "" : ", ") + e;
  if (!start.library_explains) d.with_library = fit_change(members, joint_start, nullptr, true);
  const bool joint = d.with_library.has_value();
  if (joint && d.with_library->ok &&
      d.with_library->delta_bic < std::min(d.library_delta_bic, g.delta_bic) - settings.bic_margin) {
    const GroupFit& lg = *d.with_library;
    d.held_out = compare_held_out(set, model, library_r, lg.residuals, test, settings.split_seed);
    if (d.held_out.p_value < settings.significance) {
      d.outcome = DiscoveryOutcome::with_library;
      d.verdict = "not in the library, beside " + library_names + ": " + describe_group_fit(lg) +
                  format_numbers("; delta BIC %+.4g against ", lg.delta_bic - d.library_delta_bic) + library_names +
                  " alone; " + evidence_text(d.held_out);
      return d;
    }
  }
  if (g.delta_bic < d.library_delta_bic - settings.bic_margin) {
    d.held_out = compare_held_out(set, model, base_r, g.residuals, test, settings.split_seed);
    d.against_library = compare_held_out(set, model, library_r, g.residuals, test, settings.split_seed);
    if (d.held_out.p_value < settings.significance && d.against_library.p_value < settings.significance) {
      d.outcome = DiscoveryOutcome::instead_of_library;
      d.chosen = chosen;
      mark_indistinguishable(g.delta_bic, chosen);
      d.verdict = "not in the library: " + change + ", instead of " + library_names +
                  format_numbers(" (delta BIC %+.4g against ", g.delta_bic - d.library_delta_bic) + library_names +
                  "; held-out against " + library_names + ": " + evidence_text(d.against_library) +
                  "); against the baseline: " + evidence_text(d.held_out);
      return d;
    }
  }
  d.outcome = DiscoveryOutcome::library_stands;
  mark_indistinguishable(d.library_delta_bic, std::nullopt);
  d.verdict = library_names + " stands: the best change of the base model, " + change +
              format_numbers(", has delta BIC %+.4g against ", g.delta_bic - d.library_delta_bic) + library_names +
              (joint && d.with_library->ok
                   ? format_numbers(", and beside it %+.4g", d.with_library->delta_bic - d.library_delta_bic)
                   : std::string());
  return d;
}

}  // namespace swum
