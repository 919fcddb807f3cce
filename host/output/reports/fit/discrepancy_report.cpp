#include "output/reports/fit/discrepancy_report.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "formats/number_format.h"
#include "output/plot.h"
#include "output/reports/report_values.h"

namespace swum::host {

namespace fs = std::filesystem;

namespace {

nlohmann::ordered_json evidence_json(const HeldOutEvidence& e) {
  return {{"points", e.points},           {"improved", e.improved},
          {"signed_rank", e.signed_rank}, {"signed_rank_p", e.signed_rank_p},
          {"sign_flip_p", e.sign_flip_p}, {"p_value", e.p_value},
          {"rms_before", e.rms_before},   {"rms_after", e.rms_after},
          {"reduction", e.reduction},     {"reduction_interval_90", {e.reduction_low, e.reduction_high}}};
}

// "delta BIC -725; 14 of 15 held-out points better (p 0.00012: signed-rank 6.1e-05, sign-flip 0.0002); ..."
std::string evidence_text(double delta_bic, const HeldOutEvidence& e) {
  return "delta BIC " + format_number(delta_bic, "%+.1f") + "; " + std::to_string(e.improved) + " of " +
         std::to_string(e.points) + " held-out points better (p " + format_number(e.p_value, "%.2g") +
         ": signed-rank " + format_number(e.signed_rank_p, "%.2g") + ", sign-flip " +
         format_number(e.sign_flip_p, "%.2g") + "); held-out RMS " + percent(e.rms_before) + " -> " +
         percent(e.rms_after) + ", reduction " + format_number(100.0 * e.reduction, "%.0f") + " % (90 % interval " +
         format_number(100.0 * e.reduction_low, "%.0f") + ".." + format_number(100.0 * e.reduction_high, "%.0f") +
         " %)";
}

const char* outcome_name(DiscoveryOutcome o) {
  switch (o) {
    case DiscoveryOutcome::not_run: return "not_run";
    case DiscoveryOutcome::nothing_to_explain: return "nothing_to_explain";
    case DiscoveryOutcome::nothing: return "nothing";
    case DiscoveryOutcome::alone: return "alone";
    case DiscoveryOutcome::with_library: return "with_library";
    case DiscoveryOutcome::instead_of_library: return "instead_of_library";
    case DiscoveryOutcome::library_stands: return "library_stands";
  }
  return "?";
}

nlohmann::ordered_json group_fit_json(const GroupFit& f) {
  nlohmann::ordered_json j;
  j["groups"] = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < f.groups.size(); ++k) {
    j["groups"].push_back({{"name", f.groups[k]},
                           {"keys", f.keys[k]},
                           {"change", f.changes[k] == GroupChange::shift ? "shift" : "factor"},
                           {"unit", f.units[k]},
                           {"value", f.values[k]},
                           {"standard_error", f.standard_errors[k]},
                           {"at_bound", static_cast<bool>(f.at_bound[k])}});
  }
  if (!f.effect_values.empty()) {
    j["effect_values"] = f.effect_values;
    j["effect_standard_errors"] = f.effect_standard_errors;
  }
  j["converged"] = f.ok;
  j["delta_bic"] = f.delta_bic;
  j["train_rms"] = f.train_rms;
  j["held_out_rms"] = f.held_out_rms;
  return j;
}

// Why a fitted change is not the answer, against the reference (the chosen change, or the
// library's effects when they stand).
std::string why_not(const Discovery& d, std::size_t k) {
  const GroupFit& f = d.fits[k];
  if (d.chosen && k == *d.chosen) return "chosen";
  if (std::find(d.indistinguishable.begin(), d.indistinguishable.end(), k) != d.indistinguishable.end()) {
    return "cannot be told apart from the answer on these points (within the BIC margin; not tested on the "
           "held-out points, not in augmented.toml)";
  }
  if (!f.ok) return "the fit did not converge";
  const bool against_library = !d.chosen;
  const double reference = against_library ? d.library_delta_bic : d.fits[*d.chosen].delta_bic;
  if (against_library && d.outcome != DiscoveryOutcome::library_stands) {
    return "delta BIC " + format_number(f.delta_bic, "%+.1f") + " against the baseline";
  }
  return format_number(f.delta_bic - reference, "%+.1f") + " BIC against " +
         (against_library ? std::string("the library's effects") : std::string("the chosen change"));
}

nlohmann::ordered_json discovery_json(const DiscrepancyResult& r) {
  const Discovery& d = r.discovery;
  nlohmann::ordered_json j;
  j["outcome"] = outcome_name(d.outcome);
  j["verdict"] = d.verdict;
  if (const GroupFit* a = accepted_change(d)) {
    j["change"] = group_fit_json(*a);
    j["held_out"] = evidence_json(d.held_out);
    if (d.outcome == DiscoveryOutcome::instead_of_library) {
      j["held_out_against_library"] = evidence_json(d.against_library);
    }
    if (d.outcome == DiscoveryOutcome::with_library) j["held_out_against_change"] = evidence_json(d.against_change);
  }
  j["effects_after_change"] = d.effects_after_change;
  j["library_delta_bic"] = d.library_delta_bic;
  j["fits"] = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < d.fits.size(); ++k) {
    nlohmann::ordered_json f = group_fit_json(d.fits[k]);
    f["note"] = why_not(d, k);
    j["fits"].push_back(f);
  }
  j["with_library_fits"] = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < d.with_library_fits.size(); ++k) {
    nlohmann::ordered_json f = group_fit_json(d.with_library_fits[k]);
    const bool alike = std::find(d.indistinguishable_with_library.begin(), d.indistinguishable_with_library.end(), k) !=
                       d.indistinguishable_with_library.end();
    f["note"] = k == 0 && accepted_change(d) == &d.with_library_fits[0] ? "chosen"
                : alike ? "cannot be told apart from the answer on these points (not tested on the held-out points)"
                        : "fitted beside the library's effects";
    j["with_library_fits"].push_back(f);
  }
  j["significance"] = d.significance;
  j["screened"] = nlohmann::ordered_json::array();
  for (const GroupScreening& s : d.screened) {
    nlohmann::ordered_json g{{"name", s.name}};
    if (s.note.empty()) {
      g["value"] = s.value;
      g["delta_bic"] = s.delta_bic;
    } else {
      g["note"] = s.note;
    }
    j["screened"].push_back(g);
  }
  return j;
}

nlohmann::ordered_json to_json(const DiscrepancyResult& r, double wall_s) {
  nlohmann::ordered_json j;
  j["effects"] = nlohmann::ordered_json::array();
  for (const NamedEffect& e : r.effects) {
    nlohmann::ordered_json effect;
    effect["name"] = e.name;
    effect["parameters"][e.key] = {{"value", e.value}, {"standard_error", e.standard_error}, {"unit", e.unit}};
    effect["delta_bic"] = e.delta_bic;
    effect["held_out"] = evidence_json(e.held_out);
    j["effects"].push_back(effect);
  }
  j["superseded"] = nlohmann::ordered_json::array();
  for (const NamedEffect& e : r.superseded) {
    j["superseded"].push_back({{"name", e.name}, {"key", e.key}, {"value", e.value}, {"unit", e.unit}});
  }
  j["discovery"] = discovery_json(r);
  j["held_out_points"] = r.held_out_points;
  j["operating_points"] = r.operating_points;
  j["rms_before"] = r.rms_before;
  j["rms_after"] = r.rms_after;
  nlohmann::ordered_json gaps;
  for (Quantity q : kQuantities) {
    const QuantityGap& g = r.gaps[static_cast<std::size_t>(q)];
    if (g.count == 0) continue;
    gaps[std::string(quantity_column(q))] = {{"count", g.count},
                                             {"rms_before", g.rms_before},
                                             {"max_before", g.max_before},
                                             {"rms_after", g.rms_after},
                                             {"max_after", g.max_after}};
  }
  j["gaps"] = gaps;
  j["baseline"] = {{"rms", r.baseline_map.rms},
                   {"noise", r.baseline_map.noise},
                   {"noise_source", r.baseline_map.noise_source},
                   {"structured", r.baseline_map.structured},
                   {"summary", r.baseline_map.summary}};
  j["rounds"] = nlohmann::ordered_json::array();
  for (const DiscrepancyRound& round : r.rounds) {
    nlohmann::ordered_json jr;
    jr["verdict"] = round.verdict;
    jr["after_change"] = round.after_change;
    if (round.fitted) {
      jr["fitted"] = round.candidates[*round.fitted].name;
      jr["named"] = round.accepted;
      jr["delta_bic"] = round.fitted_delta_bic;
      jr["held_out"] = evidence_json(round.held_out);
    }
    jr["candidates"] = nlohmann::ordered_json::array();
    for (const CandidateScore& c : round.candidates) {
      nlohmann::ordered_json jc{{"name", c.name}, {"skipped", c.skipped}};
      if (c.skipped) {
        jc["note"] = c.note;
      } else {
        jc["value"] = c.value;
        jc["train_rms"] = c.train_rms;
        jc["held_out_rms"] = c.held_out_rms;
        jc["delta_bic"] = c.delta_bic;
      }
      jr["candidates"].push_back(jc);
    }
    j["rounds"].push_back(jr);
  }
  j["conclusion"] = r.conclusion;
  j["model_evaluations"] = r.model_evaluations;
  j["wall_s"] = wall_s;
  return j;
}

}  // namespace

std::string discrepancy_json(const DiscrepancyResult& r, double wall_s) { return to_json(r, wall_s).dump(2) + "\n"; }

std::string discrepancy_summary_text(const DiscrepancyResult& r) {
  std::string out = "baseline: " + r.baseline_map.summary + "\n";
  for (std::size_t k = 0; k < r.rounds.size(); ++k) {
    out += "round " + std::to_string(k + 1) + (r.rounds[k].after_change ? " (on the discovery's changed model)" : "") +
           ": " + r.rounds[k].verdict + "\n";
    for (const CandidateScore& c : r.rounds[k].candidates) {
      std::string line;
      if (c.skipped) {
        line = printf_string("  %-16s skipped: %s\n", c.name.c_str(), c.note.c_str());
      } else {
        line = printf_string("  %-16s value %-10s train RMS %-8s held-out RMS %-8s dBIC %+.1f\n", c.name.c_str(),
                             format_number(c.value, "%.4g").c_str(), percent(c.train_rms).c_str(),
                             percent(c.held_out_rms).c_str(), c.delta_bic);
      }
      out += line;
    }
  }
  if (!r.discovery.verdict.empty()) {
    const Discovery& d = r.discovery;
    out += "discovery: " + d.verdict + "\n";
    for (std::size_t k = 0; k < d.fits.size(); ++k) {
      out += "  " + describe_group_fit(d.fits[k]) + "\n    train RMS " + percent(d.fits[k].train_rms) +
             ", held-out RMS " + percent(d.fits[k].held_out_rms) + ", delta BIC " +
             format_number(d.fits[k].delta_bic, "%+.1f") + ": " + why_not(d, k) + "\n";
    }
    for (const GroupFit& f : d.with_library_fits) {
      out += "  beside the library's effects: " + describe_group_fit(f) + "\n    train RMS " + percent(f.train_rms) +
             ", held-out RMS " + percent(f.held_out_rms) + ", delta BIC " + format_number(f.delta_bic, "%+.1f") + "\n";
    }
  }
  for (const NamedEffect& e : r.superseded) {
    out += "not named after all: " + e.name +
           " (the library's round named it; a change of the base model explains "
           "the data better)\n";
  }
  if (r.effects.empty()) {
    out += accepted_change(r.discovery) != nullptr ? "named effects: none (a change of the base model: see discovery)\n"
                                                   : "named effects: none\n";
  }
  for (const NamedEffect& e : r.effects) {
    out += "named effect: " + e.name + "  " + e.key + " = " + format_number(e.value, "%.4g") + " +- " +
           format_number(e.standard_error, "%.2g") + " " + e.unit +
           "\n    evidence: " + evidence_text(e.delta_bic, e.held_out) + "\n";
  }
  out += "held-out gap (relative RMS / max): " + percent(r.rms_before) + " -> " + percent(r.rms_after) + "\n";
  for (Quantity q : kQuantities) {
    const QuantityGap& g = r.gaps[static_cast<std::size_t>(q)];
    if (g.count == 0) continue;
    std::string line;
    line = printf_string("  %-18s RMS %-8s -> %-8s max %-8s -> %s\n", std::string(quantity_column(q)).c_str(),
                         percent(g.rms_before).c_str(), percent(g.rms_after).c_str(), percent(g.max_before).c_str(),
                         percent(g.max_after).c_str());
    out += line;
  }
  out += "conclusion: " + r.conclusion + "\n";
  return out;
}

// Per quantity: measured, baseline and augmented against the point index in session order;
// and the relative residuals of both models.
std::vector<std::string> write_discrepancy_plots(const fs::path& dir, const MeasurementSet& set,
                                                 const DiscrepancyResult& r) {
  std::vector<std::string> files;
  const std::vector<std::size_t> order = session_order(set.rows);
  for (Quantity q : kQuantities) {
    if (!set.has_quantity[static_cast<std::size_t>(q)]) continue;
    PlotSeries measured{"measured", {}, {}, false, true};
    PlotSeries base{"baseline model", {}, {}, true, false};
    PlotSeries augmented{"augmented model", {}, {}, true, false};
    for (std::size_t k = 0; k < order.size(); ++k) {
      const std::size_t i = order[k];
      const auto& v = set.rows[i].value(q);
      if (!v) continue;
      const double x = static_cast<double>(k);
      measured.x.push_back(x);
      measured.y.push_back(*v);
      base.x.push_back(x);
      base.y.push_back(r.baseline_predictions[i].value(q));
      augmented.x.push_back(x);
      augmented.y.push_back(r.augmented_predictions[i].value(q));
    }
    PlotSpec spec;
    spec.title = "Measured vs baseline and augmented model";
    spec.x_label = "point (session order)";
    spec.y_label = std::string(quantity_label(q));
    spec.series = {measured, base, augmented};
    const std::string name = std::string(quantity_column(q)) + ".png";
    write_png_plot(spec, dir / name);
    files.push_back(name);
  }
  return files;
}

namespace {

std::string discovery_markdown(const DiscrepancyResult& r) {
  const Discovery& d = r.discovery;
  if (d.verdict.empty()) return "";
  std::string md = "\n## Discovery beyond the library\n\n" + d.verdict + "\n\n";
  for (const NamedEffect& e : r.superseded) {
    md += "- **" + e.name + "** was named by the library's round (`" + e.key + " = " + format_number(e.value, "%.4g") +
          "`), but the change of the base model explains the data better: not in the augmented model.\n";
  }
  if (!d.fits.empty()) {
    md += "\n| change of the base model | train RMS | held-out RMS | delta BIC (baseline) | |\n|---|---|---|---|---|\n";
    for (std::size_t k = 0; k < d.fits.size(); ++k) {
      md += "| " + describe_group_fit(d.fits[k]) + " | " + percent(d.fits[k].train_rms) + " | " +
            percent(d.fits[k].held_out_rms) + " | " + format_number(d.fits[k].delta_bic, "%+.1f") + " | " +
            why_not(d, k) + " |\n";
    }
  }
  if (!d.with_library_fits.empty()) {
    md += "\nFitted jointly with the library's effects (delta BIC against the baseline, the effects counted):\n\n"
          "| change beside the library's effects | train RMS | held-out RMS | delta BIC (baseline) "
          "|\n|---|---|---|---|\n";
    for (const GroupFit& f : d.with_library_fits) {
      md += "| " + describe_group_fit(f) + " | " + percent(f.train_rms) + " | " + percent(f.held_out_rms) + " | " +
            format_number(f.delta_bic, "%+.1f") + " |\n";
    }
  }
  md += "\nScreened groups (one factor or shift each, on the baseline):\n\n| group | value | delta BIC "
        "|\n|---|---|---|\n";
  for (const GroupScreening& s : d.screened) {
    md += s.note.empty() ? "| " + s.name + " | " + format_number(s.value, "%.4g") + " | " +
                               format_number(s.delta_bic, "%+.1f") + " |\n"
                         : "| " + s.name + " | " + s.note + " | |\n";
  }
  md += "\nA change is accepted by the rule that names a library effect (below); it replaces the library's effects "
        "only when it beats them by the BIC margin on the training points and on the held-out points "
        "(docs/discrepancy.md, \"Discovery\").\n";
  return md;
}

}  // namespace

std::string discrepancy_report_markdown(const std::string& command_line, const MeasurementSet& set,
                                        const DiscrepancyResult& r, const std::vector<std::string>& plots) {
  std::string md = "# Model discrepancy report\n\n";
  md += "`swum discrepancy " + command_line + "`\n\n";
  if (const std::string note = measurement_note(set); !note.empty()) md += "Input: " + note + "\n\n";
  md += "**Conclusion:** " + r.conclusion + "\n\n";
  md += "## Disagreement map of the baseline\n\n" + r.baseline_map.summary + "\n\n";
  md += "| variable | F (quadratic trend) | R^2 | quantity | structured |\n|---|---|---|---|---|\n";
  for (const TrendTest& t : r.baseline_map.trends) {
    md += "| " + std::string(t.variable) + " | " + format_number(t.f_statistic, "%.3g") + " | " +
          format_number(t.explained_fraction, "%.2f") + " | " + std::string(quantity_column(t.quantity)) + " | " +
          (t.structured ? "yes" : "no") + " |\n";
  }
  md += "\nLargest residuals (relative):\n\n| line | quantity | measured | baseline | r |\n|---|---|---|---|---|\n";
  for (const ResidualValue& v : r.baseline_map.largest) {
    md += "| " + std::to_string(set.rows[v.slot.row].source_line) + " | " +
          std::string(quantity_column(v.slot.quantity)) + " | " + format_number(v.measured, "%.4g") + " | " +
          format_number(v.predicted, "%.4g") + " | " + percent(v.relative) + " |\n";
  }
  md += "\n## Selection\n\n";
  for (std::size_t k = 0; k < r.rounds.size(); ++k) {
    md += "Round " + std::to_string(k + 1) + (r.rounds[k].after_change ? " (on the discovery's changed model)" : "") +
          ": " + r.rounds[k].verdict + "\n\n";
    md += "| candidate | value | train RMS | held-out RMS | delta BIC |\n|---|---|---|---|---|\n";
    for (const CandidateScore& c : r.rounds[k].candidates) {
      md += c.skipped ? "| " + c.name + " | skipped: " + c.note + " | | | |\n"
                      : "| " + c.name + " | " + format_number(c.value, "%.4g") + " | " + percent(c.train_rms) + " | " +
                            percent(c.held_out_rms) + " | " + format_number(c.delta_bic, "%+.1f") + " |\n";
    }
    md += "\n";
  }
  md += "## Named effects\n\n";
  if (r.effects.empty()) md += "None.\n";
  for (const NamedEffect& e : r.effects) {
    md += "- **" + e.name + "**: `" + e.key + " = " + format_number(e.value, "%.4g") + "` +- " +
          format_number(e.standard_error, "%.2g") + " " + e.unit +
          "; evidence: " + evidence_text(e.delta_bic, e.held_out) + "\n";
  }
  md += discovery_markdown(r);
  md += "\nNamed when both hold: delta BIC on the " + std::to_string(r.operating_points - r.held_out_points) +
        " training points below -" + format_number(DiscrepancyOptions{}.bic_margin, "%g") + ", and on the " +
        std::to_string(r.held_out_points) +
        " held-out points the one-sided signed-rank and sign-flip tests, Bonferroni-combined, below p = " +
        format_number(DiscrepancyOptions{}.significance, "%g") +
        (r.discovery.significance > 0.0 && r.discovery.significance < DiscrepancyOptions{}.significance
             ? " (a change of the base model: p = " + format_number(r.discovery.significance, "%g") +
                   ", Bonferroni over the step's attempts)"
             : std::string()) +
        " (docs/discrepancy.md).\n";
  md += "\n## Gap on held-out points (relative)\n\n| quantity | n | RMS before | RMS after | max before | max after "
        "|\n|---|---|---|---|---|---|\n";
  for (Quantity q : kQuantities) {
    const QuantityGap& g = r.gaps[static_cast<std::size_t>(q)];
    if (g.count == 0) continue;
    md += "| " + std::string(quantity_column(q)) + " | " + std::to_string(g.count) + " | " + percent(g.rms_before) +
          " | " + percent(g.rms_after) + " | " + percent(g.max_before) + " | " + percent(g.max_after) + " |\n";
  }
  md += "| all | | " + percent(r.rms_before) + " | " + percent(r.rms_after) + " | | |\n\n";
  md += "Remaining residual: " + r.augmented_map.summary + "\n\n";
  for (const std::string& p : plots) md += "![" + p + "](" + p + ")\n";
  md += "\nAugmented config: `augmented.toml`. " + std::to_string(r.model_evaluations) +
        " model evaluations of every point.\n";
  return md;
}

std::string discrepancy_augmented_header(const std::string& command_line, const DiscrepancyResult& r) {
  std::string header = "# Written by `swum discrepancy " + command_line +
                       "`: the baseline plus the named effects and any change of the base model it found.\n";
  for (const NamedEffect& e : r.effects) {
    header += "#   effects." + e.name + "." + e.key + " = " + format_number(e.value, "%.6g") + " +- " +
              format_number(e.standard_error, "%.2g") + " " + e.unit + "\n";
  }
  if (const GroupFit* a = accepted_change(r.discovery)) {
    header += "#   not in the library: " + describe_group_fit(*a) + "\n";
  }
  if (r.effects.empty() && accepted_change(r.discovery) == nullptr) {
    header += "#   no effect named: identical to the baseline\n";
  }
  return header;
}

}  // namespace swum::host
