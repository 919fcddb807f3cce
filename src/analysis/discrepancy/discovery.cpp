#include "analysis/discrepancy/discovery.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "analysis/discrepancy/candidate_effects.h"
#include "analysis/discrepancy/candidate_fitting.h"
#include "formats/number_format.h"

namespace swum {
namespace {

// The groups to search, with their free parameters around the baseline.
struct Group {
  const ParameterGroup* group;
  FreeParameter free;
};

std::vector<Group> groups_for(const MotorParameters& baseline, const DiscoveryOptions& options,
                              std::vector<GroupScreening>& screened) {
  validate_discovery_groups(options, baseline);
  std::vector<const ParameterGroup*> wanted;
  if (options.groups.empty()) {
    for (const ParameterGroup& g : parameter_groups()) wanted.push_back(&g);
  } else {
    for (const std::string& name : options.groups) wanted.push_back(find_parameter_group(name));
  }
  std::vector<Group> out;
  for (const ParameterGroup* g : wanted) {
    GroupScreening s;
    s.name = std::string(g->name);
    s.note = group_not_applicable_reason(*g, baseline);
    if (s.note.empty()) out.push_back({g, group_free_parameter(*g, baseline)});
    screened.push_back(s);
  }
  return out;
}

bool near_bound(const FreeParameter& f, double value) {
  const double tolerance = 1e-3 * std::abs(f.scale);
  return std::abs(value - f.lower) < tolerance || std::abs(value - f.upper) < tolerance;
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::string p_text(const HeldOutEvidence& e, double level) {
  return format_numbers("held-out p = %.3g", e.p_value) + (e.p_value < level ? " below " : " not below ") +
         format_numbers("%.3g", level);
}

// What the step works with: the groups, the data, the training and held-out slots.
class Search {
 public:
  Search(const DiscoveryStart& start, const MeasurementSet& set, const ResidualModel& model,
         std::span<const std::size_t> train, const DiscoverySettings& settings, const ParallelFor& parallel,
         int& counter, std::vector<Group> groups)
      : start_(start),
        set_(set),
        model_(model),
        train_(train),
        settings_(settings),
        parallel_(parallel),
        counter_(counter),
        groups_(std::move(groups)) {
    for (std::size_t k : train_) {
      const std::size_t row = model_.slots()[k].row;
      if (train_rows_.empty() || train_rows_.back() != row) train_rows_.push_back(row);
    }
    std::sort(train_rows_.begin(), train_rows_.end());
    train_rows_.erase(std::unique(train_rows_.begin(), train_rows_.end()), train_rows_.end());
  }

  [[nodiscard]] const std::vector<Group>& groups() const { return groups_; }

  // Whether `p` leaves a structured residual on the training rows (the held-out rows must not
  // decide which hypothesis they then test).
  [[nodiscard]] bool structured(const Predictions& p) const {
    return map_disagreement(set_, p, model_, train_rows_).structured;
  }

  // Every group screened in both directions on top of `origin` (the better side kept).
  [[nodiscard]] std::vector<Screened> screen(const MotorParameters& origin, const Predictions& predictions,
                                             const std::vector<double>& r) const {
    // Unlike an effect, a change of the base model has no sign known in advance, and where it
    // moves the fold a step the wrong way can leave the secant nowhere to go: each group is
    // probed up and down, the two directions one family (one follow-up place between them).
    std::vector<std::optional<FreeParameter>> free;
    ScreeningSettings s{settings_.screening_steps, settings_.bic_margin, scale_of(r), {}, 3};
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      free.emplace_back(groups_[g].free);
      FreeParameter down = groups_[g].free;
      down.scale = -down.scale;
      free.emplace_back(down);
      s.families.push_back(g);
      s.families.push_back(g);
    }
    const std::vector<Screened> both = screen_candidates(origin, free, predictions, r, model_, train_, s, predictor());
    std::vector<Screened> out;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      Screened up = both[2 * g];
      Screened down = both[2 * g + 1];
      down.theta = -down.theta;  // in the group's own direction
      out.push_back(down.robust < up.robust ? std::move(down) : std::move(up));
    }
    return out;
  }

  [[nodiscard]] double value_of(std::size_t g, const Screened& s) const {
    return groups_[g].free.origin + s.theta * groups_[g].free.scale;
  }

  // The change `members` fitted from `values`, on the baseline or jointly with the library's
  // effects (their values first). delta_bic is against the baseline, every fitted parameter
  // counted.
  [[nodiscard]] GroupFit fit(const std::vector<std::size_t>& members, const std::vector<double>& values,
                             const Predictions* start_predictions, bool with_library) const {
    std::vector<FreeParameter> parameters;
    std::vector<double> start;
    if (with_library) {
      for (std::size_t k = 0; k < start_.library_effects.size(); ++k) {
        parameters.push_back(effect_free_parameter(*find_candidate_effect(start_.library_effects[k])));
        start.push_back(start_.library_values[k]);
      }
    }
    for (std::size_t m : members) parameters.push_back(groups_[m].free);
    start.insert(start.end(), values.begin(), values.end());
    const MotorParameters& origin = with_library ? *start_.library : *start_.baseline;
    const std::vector<double> origin_r = model_.residuals(with_library ? *start_.library_predictions
                                                                       : *start_.baseline_predictions);
    const ParameterEvaluator eval(origin, parameters, set_, settings_.prediction, parallel_, counter_);
    const ParameterFit fit = fit_candidate(eval, model_, train_, start, start_predictions, scale_of(origin_r),
                                           settings_.robust, settings_.max_fit_iterations);
    GroupFit out;
    const std::size_t first = with_library ? start_.library_effects.size() : 0;
    for (std::size_t k = 0; k < first; ++k) {
      out.effect_values.push_back(fit.values[k]);
      out.effect_standard_errors.push_back(fit.standard_errors[k]);
    }
    for (std::size_t k = 0; k < members.size(); ++k) {
      const Group& g = groups_[members[k]];
      out.groups.emplace_back(g.group->name);
      out.changes.push_back(g.group->change);
      out.units.push_back(g.free.unit);
      std::vector<std::string> keys;
      for (const ParameterSpec* spec : group_parameters(*g.group, *start_.baseline)) keys.push_back(spec->name());
      out.keys.push_back(std::move(keys));
      out.values.push_back(fit.values[first + k]);
      out.standard_errors.push_back(fit.standard_errors[first + k]);
      out.at_bound.push_back(near_bound(g.free, fit.values[first + k]));
    }
    out.ok = fit.ok;
    out.residuals = model_.residuals(fit.predictions);
    out.delta_bic = delta_bic(fit.train_sum_of_squares, sse0(), train_.size(), static_cast<int>(parameters.size()));
    out.train_rms = std::sqrt(fit.train_sum_of_squares / static_cast<double>(std::max<std::size_t>(train_.size(), 1)));
    out.parameters = eval.parameters_at(fit.values);
    out.predictions = fit.predictions;
    return out;
  }

  [[nodiscard]] double sse0() const { return sum_of_squares(model_.residuals(*start_.baseline_predictions), train_); }

  [[nodiscard]] BatchPredictor predictor() const {
    return [this](const std::vector<MotorParameters>& models) {
      counter_ += static_cast<int>(models.size());
      return predict_points(models, set_.rows, settings_.prediction, parallel_);
    };
  }

 private:
  [[nodiscard]] double scale_of(const std::vector<double>& r) const {
    return kCauchyEfficiencyScale * robust_sigma(r, train_);
  }

  const DiscoveryStart& start_;
  const MeasurementSet& set_;
  const ResidualModel& model_;
  std::span<const std::size_t> train_;
  const DiscoverySettings& settings_;
  const ParallelFor& parallel_;
  int& counter_;
  std::vector<Group> groups_;
  std::vector<std::size_t> train_rows_;
};

// Usable fits first, then by delta BIC (a non-finite one, from a diverged fit, last).
double bic_key(const GroupFit& f) {
  return std::isfinite(f.delta_bic) ? f.delta_bic : std::numeric_limits<double>::infinity();
}
bool by_bic(const GroupFit& a, const GroupFit& b) { return a.ok != b.ok ? a.ok : bic_key(a) < bic_key(b); }

// The best usable fit, preferring fewer groups within the margin (the smallest change).
std::optional<std::size_t> smallest_best(const std::vector<GroupFit>& fits, double margin) {
  std::optional<std::size_t> chosen;
  for (std::size_t k = 0; k < fits.size(); ++k) {
    if (!fits[k].ok) continue;
    if (!chosen ||
        (fits[k].groups.size() < fits[*chosen].groups.size() && fits[k].delta_bic < fits[*chosen].delta_bic + margin)) {
      chosen = k;
    }
  }
  return chosen;
}

}  // namespace

const GroupFit* accepted_change(const Discovery& d) {
  if ((d.outcome == DiscoveryOutcome::with_library || d.effects_after_change) && !d.with_library_fits.empty()) {
    return &d.with_library_fits[0];
  }
  if (d.chosen && (d.outcome == DiscoveryOutcome::alone || d.outcome == DiscoveryOutcome::instead_of_library)) {
    return &d.fits[*d.chosen];
  }
  return nullptr;
}

void validate_discovery_groups(const DiscoveryOptions& options, const MotorParameters& baseline) {
  for (const std::string& name : options.groups) {
    const ParameterGroup* g = find_parameter_group(name);
    if (g == nullptr) {
      throw std::invalid_argument("unknown group '" + name + "' (known: " + parameter_group_names() + ")");
    }
    if (std::count(options.groups.begin(), options.groups.end(), name) > 1) {
      throw std::invalid_argument("group '" + name + "' is named twice");
    }
    if (const std::string why = group_not_applicable_reason(*g, baseline); !why.empty()) {
      throw std::invalid_argument("group '" + name + "' does not apply to this config (" + why + ")");
    }
  }
}

GroupFit refit_change_with_effects(const GroupFit& change, const std::vector<std::string>& effects,
                                   const std::vector<double>& effect_values, const MotorParameters& baseline,
                                   const Predictions& baseline_predictions, const MeasurementSet& set,
                                   const ResidualModel& model, std::span<const std::size_t> train,
                                   std::span<const std::size_t> test, const DiscoverySettings& settings,
                                   const ParallelFor& parallel, int& evaluation_counter) {
  const DiscoveryStart start{&baseline, &baseline_predictions, &baseline, &baseline_predictions,
                             effects,   effect_values,         false};
  std::vector<Group> groups;
  std::vector<std::size_t> members;
  for (const std::string& name : change.groups) {
    const ParameterGroup* g = find_parameter_group(name);
    members.push_back(groups.size());
    groups.push_back({g, group_free_parameter(*g, baseline)});
  }
  const Search search(start, set, model, train, settings, parallel, evaluation_counter, std::move(groups));
  GroupFit joint = search.fit(members, change.values, nullptr, true);
  joint.held_out_rms = rms_of(joint.residuals, test);
  return joint;
}

std::string describe_group_fit(const GroupFit& fit) {
  std::string out;
  for (std::size_t k = 0; k < fit.groups.size(); ++k) {
    if (!out.empty()) out += " and ";
    const bool shift = fit.changes[k] == GroupChange::shift;
    out += fit.groups[k] + " " +
           (shift ? format_numbers("%+.4g", fit.values[k]) : format_numbers("x%.4g", fit.values[k]));
    if (fit.at_bound[k]) {
      out += " (at its bound: the data push it further; no standard error)";
    } else {
      out += std::isfinite(fit.standard_errors[k]) ? format_numbers(" +- %.2g", fit.standard_errors[k])
                                                   : std::string(" (standard error unknown)");
    }
    if (shift) out += " " + fit.units[k];
    out += " (" + join(fit.keys[k]) + (fit.keys[k].size() > 1 ? " together)" : ")");
  }
  return out;
}

Discovery run_discovery(const DiscoveryStart& start, const MeasurementSet& set, const ResidualModel& model,
                        std::span<const std::size_t> train, std::span<const std::size_t> test,
                        const DiscoverySettings& settings, const ParallelFor& parallel, int& evaluation_counter) {
  Discovery d;
  if (!settings.options.enabled) return d;
  const MotorParameters& baseline = *start.baseline;
  const bool beside_possible = !start.library_effects.empty() && !start.library_explains;
  d.significance = settings.significance / (beside_possible ? 2.0 : 1.0);
  std::vector<Group> groups = groups_for(baseline, settings.options, d.screened);
  if (groups.empty()) {
    d.outcome = DiscoveryOutcome::nothing;
    d.verdict = "no group of base parameters applies to this config";
    return d;
  }
  const Search search(start, set, model, train, settings, parallel, evaluation_counter, std::move(groups));
  const std::vector<Group>& g_all = search.groups();
  const std::size_t n = train.size();
  const std::vector<double> base_r = model.residuals(*start.baseline_predictions);
  const std::vector<double> library_r = model.residuals(*start.library_predictions);
  const double sse0 = sum_of_squares(base_r, train);
  const int library_count = static_cast<int>(start.library_effects.size());
  const std::string library_names = join(start.library_effects);
  d.library_delta_bic = library_count == 0 ? 0.0 : delta_bic(sum_of_squares(library_r, train), sse0, n, library_count);

  // 1. Screening of every group on the baseline.
  const std::vector<Screened> screened = search.screen(baseline, *start.baseline_predictions, base_r);
  std::vector<double> screened_bic;
  std::vector<std::size_t> order;  // groups by screened robust cost
  for (std::size_t g = 0; g < g_all.size(); ++g) {
    order.push_back(g);
    screened_bic.push_back(delta_bic(screened[g].sse, sse0, n, 1));
    for (GroupScreening& s : d.screened) {
      if (s.name != g_all[g].group->name) continue;
      s.value = search.value_of(g, screened[g]);
      s.delta_bic = screened_bic[g];
    }
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return screened[a].robust < screened[b].robust; });

  // 2. Full fits on the baseline: the best screened groups that could pass the margin (where the
  // library's residual is within the noise, only those that could come within the margin of it).
  std::vector<std::size_t> singles;
  for (std::size_t g : order) {
    if (static_cast<int>(singles.size()) >= settings.options.fitted_singles) break;
    if (screened_bic[g] < -settings.bic_margin &&
        (!start.library_explains || screened_bic[g] < d.library_delta_bic + settings.bic_margin)) {
      singles.push_back(g);
    }
  }
  for (std::size_t g : singles) {
    d.fits.push_back(search.fit({g}, {search.value_of(g, screened[g])}, &screened[g].predictions, false));
  }
  std::stable_sort(d.fits.begin(), d.fits.end(), by_bic);
  // Pairs of the best screened groups when the best single change leaves a structured
  // residual on the training rows (a second change asked for by the data, not tried always).
  if (settings.options.pairs && !start.library_explains && g_all.size() >= 2 && !d.fits.empty() && d.fits.front().ok &&
      search.structured(d.fits.front().predictions)) {
    // The three best screened groups that share no key (two groups that change one key are not a
    // pair: one would only take from the other).
    std::vector<std::size_t> top;
    auto keys_of = [&](std::size_t g) { return group_parameters(*g_all[g].group, baseline); };
    for (std::size_t g : order) {
      if (top.size() == 3) break;
      if (!(screened_bic[g] < 0.0)) continue;  // never improved on the baseline: no partner
      const std::vector<const ParameterSpec*> keys = keys_of(g);
      const bool overlaps = std::any_of(top.begin(), top.end(), [&](std::size_t t) {
        const std::vector<const ParameterSpec*> other = keys_of(t);
        return std::any_of(keys.begin(), keys.end(), [&](const ParameterSpec* k) {
          return std::find(other.begin(), other.end(), k) != other.end();
        });
      });
      if (!overlaps) top.push_back(g);
    }
    auto start_of = [&](std::size_t g) {
      for (const GroupFit& f : d.fits) {
        if (f.groups.size() == 1 && f.groups[0] == g_all[g].group->name) return f.values[0];
      }
      return search.value_of(g, screened[g]);
    };
    for (std::size_t a = 0; a < top.size(); ++a) {
      for (std::size_t b = a + 1; b < top.size(); ++b) {
        // A pair that is a library effect under another name is the library's to name.
        if (!library_effect_of_pair(*g_all[top[a]].group, *g_all[top[b]].group).empty()) continue;
        d.fits.push_back(search.fit({top[a], top[b]}, {start_of(top[a]), start_of(top[b])}, nullptr, false));
      }
    }
    std::stable_sort(d.fits.begin(), d.fits.end(), by_bic);
  }
  for (GroupFit& f : d.fits) f.held_out_rms = rms_of(f.residuals, test);
  const std::optional<std::size_t> best = smallest_best(d.fits, settings.bic_margin);
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
  auto alternatives_text = [&] {
    std::string out;
    for (std::size_t k : d.indistinguishable) out += (out.empty() ? "" : "; ") + describe_group_fit(d.fits[k]);
    return out.empty() ? out : "; as well explained on these points by " + out + " (not tested on the held-out points)";
  };
  const std::string best_screened = " (best screened: " + std::string(g_all[order.front()].group->name) +
                                    format_numbers(", delta BIC %+.4g against the baseline)",
                                                   screened_bic[order.front()]);

  // 3. Against the library.
  if (library_count == 0) {
    if (!best) {
      d.outcome = DiscoveryOutcome::nothing;
      d.verdict = d.fits.empty() ? "no group of base parameters lowers the BIC by more than " +
                                       format_numbers("%.3g", settings.bic_margin) + best_screened
                                 : "no fit of a group of base parameters converged to a usable solution";
      return d;
    }
    const GroupFit& g = d.fits[*best];
    d.held_out = compare_held_out(set, model, base_r, g.residuals, test, settings.split_seed);
    if (g.delta_bic < -settings.bic_margin && d.held_out.p_value < d.significance) {
      d.outcome = DiscoveryOutcome::alone;
      d.chosen = best;
      mark_indistinguishable(g.delta_bic, best);
      d.verdict = "not in the library: " + describe_group_fit(g) + "; " + describe_evidence(g.delta_bic, d.held_out) +
                  alternatives_text();
    } else {
      d.outcome = DiscoveryOutcome::nothing;
      d.verdict = "the best change of the base model, " + describe_group_fit(g) + ", is not named: " +
                  (g.delta_bic < -settings.bic_margin ? p_text(d.held_out, d.significance)
                                                      : format_numbers("delta BIC %+.3g is not below -", g.delta_bic) +
                                                            format_numbers("%.3g", settings.bic_margin)) +
                  format_numbers("; held-out RMS %.3g %% -> %.3g %%", 100.0 * d.held_out.rms_before,
                                 100.0 * d.held_out.rms_after);
    }
    return d;
  }

  std::string beside_note;
  // 3a. Beside the library's effects: the groups screened again on the library's model, the
  // best (at most three) fitted jointly with its effects; the lowest BIC is the candidate.
  std::optional<GroupFit> own;  // the beside candidate's change without the effects, on the baseline
  bool beside_candidate = false;
  if (beside_possible) {
    const std::vector<Screened> on_library = search.screen(*start.library, *start.library_predictions, library_r);
    const double library_sse = sum_of_squares(library_r, train);
    std::vector<std::size_t> lib_order;
    for (std::size_t g = 0; g < g_all.size(); ++g) {
      if (delta_bic(on_library[g].sse, library_sse, n, 1) < -settings.bic_margin) lib_order.push_back(g);
    }
    std::stable_sort(lib_order.begin(), lib_order.end(),
                     [&](std::size_t a, std::size_t b) { return on_library[a].robust < on_library[b].robust; });
    if (lib_order.size() > 3) lib_order.resize(3);
    for (std::size_t g : lib_order) {
      d.with_library_fits.push_back(
          search.fit({g}, {search.value_of(g, on_library[g])}, &on_library[g].predictions, true));
    }
    std::stable_sort(d.with_library_fits.begin(), d.with_library_fits.end(), by_bic);
    for (GroupFit& f : d.with_library_fits) f.held_out_rms = rms_of(f.residuals, test);
    if (!d.with_library_fits.empty() && !d.with_library_fits[0].ok) {
      beside_note = "; beside " + library_names + ", the joint fit of " + d.with_library_fits[0].groups[0] +
                    " did not converge to a usable solution";
    }
    if (!d.with_library_fits.empty() && d.with_library_fits[0].ok) {
      const GroupFit& lg = d.with_library_fits[0];
      // The same change without the library's effects, on the baseline: the effects must still
      // help once the change is in (the margin and the held-out test against it).
      for (const GroupFit& f : d.fits) {
        if (f.ok && f.groups == lg.groups) own = f;
      }
      if (!own) {
        std::vector<std::size_t> members;
        for (const std::string& name : lg.groups) {
          for (std::size_t k = 0; k < g_all.size(); ++k) {
            if (g_all[k].group->name == name) members.push_back(k);
          }
        }
        own = search.fit(members, lg.values, nullptr, false);
      }
      const double alone_bic = own->ok ? own->delta_bic : 0.0;
      beside_candidate = lg.delta_bic < std::min(d.library_delta_bic, alone_bic) - settings.bic_margin;
      if (!beside_candidate) {
        beside_note = "; beside " + library_names + ", the best change " + describe_group_fit(lg) +
                      format_numbers(" lowers the BIC by %.4g",
                                     std::min(d.library_delta_bic, alone_bic) - lg.delta_bic) +
                      format_numbers(", not by the margin %.3g", settings.bic_margin);
      }
    }
  }
  // 3b. Instead of the library's effects: a change alone that beats them by the margin.
  const bool instead_candidate = best && d.fits[*best].delta_bic < d.library_delta_bic - settings.bic_margin;
  // Both candidates are tried in the order of the smaller model: the change alone first, unless
  // the change beside the effects is better by the margin.
  const bool instead_first = instead_candidate &&
                             (!beside_candidate ||
                              d.fits[*best].delta_bic <= d.with_library_fits[0].delta_bic + settings.bic_margin);
  auto try_beside = [&] {
    const GroupFit& lg = d.with_library_fits[0];
    d.held_out = compare_held_out(set, model, library_r, lg.residuals, test, settings.split_seed);
    d.against_change = compare_held_out(set, model, own->residuals, lg.residuals, test, settings.split_seed);
    if (d.held_out.p_value < d.significance && d.against_change.p_value < d.significance) {
      d.outcome = DiscoveryOutcome::with_library;
      std::string others;
      for (std::size_t k = 1; k < d.with_library_fits.size(); ++k) {
        const GroupFit& f = d.with_library_fits[k];
        if (f.ok && f.delta_bic - lg.delta_bic <= settings.bic_margin) {
          d.indistinguishable_with_library.push_back(k);
          others += (others.empty() ? "" : "; ") + describe_group_fit(f);
        }
      }
      d.verdict = "not in the library, beside " + library_names + ": " + describe_group_fit(lg) + "; " +
                  describe_evidence(lg.delta_bic - d.library_delta_bic, d.held_out) + " (against " + library_names +
                  " alone); against the change alone: " + p_text(d.against_change, d.significance) +
                  (others.empty() ? ""
                                  : "; as well explained on these points by " + others +
                                        " beside it (not tested on the held-out points)");
      return true;
    }
    beside_note += "; beside " + library_names + ", " + describe_group_fit(lg) +
                   " is not named: " + p_text(d.held_out, d.significance) + " against " + library_names + " alone, " +
                   p_text(d.against_change, d.significance) + " against the change alone";
    return false;
  };
  auto try_instead = [&] {
    const GroupFit& g = d.fits[*best];
    d.held_out = compare_held_out(set, model, base_r, g.residuals, test, settings.split_seed);
    d.against_library = compare_held_out(set, model, library_r, g.residuals, test, settings.split_seed);
    if (d.held_out.p_value < d.significance && d.against_library.p_value < d.significance) {
      d.outcome = DiscoveryOutcome::instead_of_library;
      d.chosen = best;
      mark_indistinguishable(g.delta_bic, best);
      d.verdict = "not in the library: " + describe_group_fit(g) + ", instead of " + library_names + " (" +
                  describe_evidence(g.delta_bic - d.library_delta_bic, d.against_library) + ", against " +
                  library_names + "); against the baseline: " + describe_evidence(g.delta_bic, d.held_out) +
                  alternatives_text();
      return true;
    }
    beside_note += "; instead of " + library_names + ", " + describe_group_fit(g) +
                   " is not named: " + p_text(d.against_library, d.significance) + " against " + library_names + ", " +
                   p_text(d.held_out, d.significance) + " against the baseline";
    return false;
  };
  if (instead_first) {
    if (try_instead() || (beside_candidate && try_beside())) return d;
  } else {
    if ((beside_candidate && try_beside()) || (instead_candidate && try_instead())) return d;
  }
  d.outcome = DiscoveryOutcome::library_stands;
  mark_indistinguishable(d.library_delta_bic, std::nullopt);
  if (!best) {
    d.verdict = library_names + " stands: " +
                (d.fits.empty() ? std::string("no change of the base model lowers the BIC by the margin") +
                                      (start.library_explains ? " and comes within it of the library's effects" : "")
                                : std::string("no fit of a change of the base model converged to a usable solution")) +
                best_screened.substr(0, best_screened.size() - 1) +
                format_numbers("; the library's effects %+.4g)", d.library_delta_bic) + beside_note;
  } else {
    d.verdict = library_names + " stands: the best change of the base model, " + describe_group_fit(d.fits[*best]) +
                format_numbers(", has delta BIC %+.4g against it", d.fits[*best].delta_bic - d.library_delta_bic) +
                beside_note + alternatives_text();
  }
  return d;
}

}  // namespace swum
