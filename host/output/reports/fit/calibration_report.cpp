#include "output/reports/fit/calibration_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "formats/number_format.h"
#include "output/plot.h"
#include "output/reports/report_values.h"

namespace swum::host {

namespace fs = std::filesystem;

namespace {

std::string number(double v, const char* format = "%.6g") {
  if (std::isfinite(v)) return format_number(v, format);
  return std::isnan(v) ? "n/a" : (v > 0.0 ? "inf" : "-inf");
}

nlohmann::ordered_json to_json(const CalibrationResult& r, bool measured, double wall_s) {
  nlohmann::ordered_json j;
  j["parameters"] = nlohmann::ordered_json::array();
  for (const CalibratedParameter& p : r.parameters) {
    j["parameters"].push_back({{"name", p.name},
                               {"unit", p.unit},
                               {"prior", p.prior},
                               {"spread", p.spread},
                               {"value", p.value},
                               {"standard_error", finite_or_null(p.standard_error)},
                               {"identifiable", p.identifiable},
                               {"at_bound", p.at_bound},
                               {"bounds", {p.lower, p.upper}},
                               {"reason", p.reason}});
  }
  j["selection"] = nlohmann::ordered_json::array();
  for (const CandidateInformation& c : r.selection) {
    j["selection"].push_back({{"name", c.name},
                              {"expected_standard_error_spreads", finite_or_null(c.expected_standard_error)},
                              {"selected", c.selected},
                              {"reason", c.reason}});
  }
  nlohmann::ordered_json names = nlohmann::ordered_json::array();
  for (const CalibratedParameter& p : r.parameters) {
    if (p.identifiable) names.push_back(p.name);
  }
  j["correlations"] = {{"names", names}, {"matrix", r.correlations}};
  if (measured) {
    j["measurements"] = {{"operating_points", r.operating_points},
                         {"held_out_points", r.held_out_points},
                         {"noise", r.noise},
                         {"noise_source", r.noise_source},
                         {"train_rms_prior", r.train_rms_prior},
                         {"train_rms", r.train_rms},
                         {"held_out_rms_prior", r.held_out_rms_prior},
                         {"held_out_rms", r.held_out_rms},
                         {"held_out_p_value", r.held_out_evidence.p_value}};
  }
  j["facts"] = nlohmann::ordered_json::array();
  for (const FactOutcome& f : r.facts) {
    j["facts"].push_back({{"id", f.id},
                          {"unit", f.unit},
                          {"band", {finite_or_null(f.min), finite_or_null(f.max)}},
                          {"prior_value", finite_or_null(f.prior_value)},
                          {"value", finite_or_null(f.value)},
                          {"explored_value", finite_or_null(f.explored_value)},
                          {"holds_prior", f.holds_prior},
                          {"holds", f.holds},
                          {"holds_explored", f.holds_explored}});
  }
  j["explored"] = nlohmann::ordered_json::object();
  for (const auto& [name, value] : r.explored) j["explored"][name] = value;
  j["reach"] = nlohmann::ordered_json::array();
  for (const FactReach& f : r.reach) {
    j["reach"].push_back(
        {{"id", f.id}, {"reachable", f.reachable}, {"value", finite_or_null(f.value)}, {"breaks", f.breaks}});
  }
  j["fronts"] = nlohmann::ordered_json::array();
  for (const FactFront& f : r.fronts) {
    nlohmann::ordered_json points = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < f.weights.size(); ++k) {
      points.push_back({{"weight", f.weights[k]},
                        {"first", finite_or_null(f.first_values[k])},
                        {"second", finite_or_null(f.second_values[k])},
                        {"first_miss", f.first_misses[k]},
                        {"second_miss", f.second_misses[k]}});
    }
    j["fronts"].push_back({{"first", f.first}, {"second", f.second}, {"points", points}});
  }
  j["rounds"] = r.rounds;
  j["starts"] = r.starts_run;
  j["model_evaluations"] = r.model_evaluations;
  j["conclusion"] = r.conclusion;
  j["wall_s"] = wall_s;
  return j;
}

std::string parameters_text(const CalibrationResult& r) {
  std::string out;
  for (const CalibratedParameter& p : r.parameters) {
    std::string line;
    if (p.identifiable) {
      line = printf_string("  %-34s %-12s +- %-9s %s (prior %s)%s\n", p.name.c_str(), number(p.value).c_str(),
                           number(p.standard_error, "%.2g").c_str(), p.unit.c_str(), number(p.prior).c_str(),
                           p.at_bound ? "  AT A BOUND" : "");
    } else {
      line = printf_string("  %-34s not identifiable: %s\n", p.name.c_str(), p.reason.c_str());
    }
    out += line;
  }
  return out;
}

}  // namespace

std::string calibration_json(const CalibrationResult& r, bool measured, double wall_s) {
  return to_json(r, measured, wall_s).dump(2) + "\n";
}

std::string calibration_summary_text(const CalibrationResult& r, bool measured) {
  std::string out;
  if (!r.selection.empty()) {
    out += "free set (Fisher information at the prior):\n";
    for (const CandidateInformation& c : r.selection) {
      out += "  " + c.name + (c.selected ? ": selected" : ": " + c.reason) + "\n";
    }
  }
  out += "parameters:\n" + parameters_text(r);
  if (measured) {
    out += "training RMS " + percent(r.train_rms_prior) + " -> " + percent(r.train_rms) + "; held-out RMS " +
           percent(r.held_out_rms_prior) + " -> " + percent(r.held_out_rms) + " on " +
           std::to_string(r.held_out_points) + " of " + std::to_string(r.operating_points) +
           " operating points (noise estimate " + percent(r.noise) + ", " + r.noise_source + ")\n";
  }
  for (const FactOutcome& f : r.facts) {
    out += "fact " + f.id + ": " + number(f.prior_value) + " -> " + number(f.value) + " " + f.unit + " (band " +
           number(f.min) + ".." + number(f.max) + ") " + (f.holds ? "holds" : "FAILS") +
           "; every free parameter moving: " + number(f.explored_value) + (f.holds_explored ? " holds" : " fails") +
           "\n";
  }
  if (!r.explored.empty()) {
    out += "first fit, every free parameter moving:";
    for (const auto& [name, value] : r.explored) out += " " + name + " = " + number(value);
    out += "\n";
  }
  for (const FactReach& f : r.reach) {
    std::string breaks;
    for (const std::string& b : f.breaks) breaks += (breaks.empty() ? "" : ", ") + b;
    out += "pushed " + f.id + ": " + (f.reachable ? "holds" : "still fails") + " at " + number(f.value) +
           (breaks.empty() ? "" : "; then lose (miss grows): " + breaks) + "\n";
  }
  for (const FactFront& f : r.fronts) {
    out += "front " + f.first + " vs " + f.second + " (weight: first, second):\n";
    for (std::size_t k = 0; k < f.weights.size(); ++k) {
      out += "  " + number(f.weights[k], "%g") + ": " + number(f.first_values[k]) + ", " + number(f.second_values[k]) +
             "\n";
    }
  }
  out += "conclusion: " + r.conclusion + "\n";
  return out;
}

// Measured against prior and fitted speed over frequency, one plot per load, one curve per
// voltage (and per tip amplitude, where measured).
std::vector<std::string> write_calibration_plots(const fs::path& dir, const MeasurementSet& set,
                                                 const CalibrationResult& r) {
  std::vector<std::string> files;
  std::set<double> loads;
  for (const Measurement& m : set.rows) loads.insert(m.load_n);
  for (Quantity q : kQuantities) {
    const auto qi = static_cast<std::size_t>(q);
    if (!set.has_quantity[qi]) continue;
    for (double load : loads) {
      std::map<double, std::vector<std::size_t>> by_amplitude_v;
      for (std::size_t i = 0; i < set.rows.size(); ++i) {
        if (set.rows[i].load_n == load && set.rows[i].value(q)) by_amplitude_v[set.rows[i].amplitude_v].push_back(i);
      }
      if (by_amplitude_v.empty()) continue;
      PlotSpec spec;
      spec.title = "Measured (points) vs prior (dashed) and calibrated (line), load " + number(load, "%g") + " N";
      spec.x_label = "frequency (Hz)";
      spec.y_label = std::string(quantity_label(q));
      for (auto& [amplitude_v, rows] : by_amplitude_v) {
        std::sort(rows.begin(), rows.end(),
                  [&](std::size_t a, std::size_t b) { return set.rows[a].frequency_hz < set.rows[b].frequency_hz; });
        const std::string v = number(amplitude_v, "%g") + " V";
        PlotSeries measured{v + " measured", {}, {}, false, true, false};
        PlotSeries prior{v + " prior", {}, {}, true, false, true};
        PlotSeries fitted{v + " calibrated", {}, {}, true, false, false};
        for (std::size_t i : rows) {
          const double f = set.rows[i].frequency_hz;
          measured.x.push_back(f);
          measured.y.push_back(*set.rows[i].value(q));
          prior.x.push_back(f);
          prior.y.push_back(r.prior_predictions[i].value(q));
          fitted.x.push_back(f);
          fitted.y.push_back(r.fitted_predictions[i].value(q));
        }
        spec.series.push_back(measured);
        spec.series.push_back(prior);
        spec.series.push_back(fitted);
      }
      const std::string name = std::string(quantity_column(q)) + "_load_" + number(load, "%g") + "N.png";
      write_png_plot(spec, dir / name);
      files.push_back(name);
    }
  }
  return files;
}

std::string calibration_report_markdown(const std::string& command_line, const MeasurementSet* set,
                                        const CalibrationResult& r, const std::vector<std::string>& plots,
                                        double wall_s) {
  std::string md = "# Calibration report\n\n`swum calibrate " + command_line + "`\n\n**Conclusion:** " + r.conclusion +
                   "\n\n";
  if (set != nullptr) {
    if (const std::string note = measurement_note(*set); !note.empty()) md += "Input: " + note + "\n\n";
  }
  if (!r.selection.empty()) {
    md += "## Free set (Fisher information of the design at the prior)\n\n| candidate | expected SE alone "
          "(spreads) | verdict |\n|---|---|---|\n";
    for (const CandidateInformation& c : r.selection) {
      md += "| `" + c.name + "` | " + number(c.expected_standard_error, "%.3g") + " | " +
            (c.selected ? std::string("selected") : c.reason) + " |\n";
    }
    md += "\n";
  }
  md +=
      "## Parameters\n\n| parameter | prior | fitted | standard error | unit | verdict |\n|---|---|---|---|---|---|\n";
  for (const CalibratedParameter& p : r.parameters) {
    md += "| `" + p.name + "` | " + number(p.prior) + " | " + number(p.value) + " | " +
          number(p.standard_error, "%.2g") + " | " + p.unit + " | " +
          (p.identifiable ? (p.at_bound ? "identified, at a bound" : "identified") : p.reason) + " |\n";
  }
  if (!r.correlations.empty()) {
    std::vector<std::string> names;
    for (const CalibratedParameter& p : r.parameters) {
      if (p.identifiable) names.push_back(p.name);
    }
    md += "\nCorrelations of the identified estimates:\n\n| |";
    for (const std::string& n : names) md += " `" + n + "` |";
    md += "\n|---|";
    for (std::size_t k = 0; k < names.size(); ++k) md += "---|";
    md += "\n";
    for (std::size_t a = 0; a < names.size() && a < r.correlations.size(); ++a) {
      md += "| `" + names[a] + "`";
      for (std::size_t b = 0; b < names.size(); ++b) md += " | " + number(r.correlations[a][b], "%+.2f");
      md += " |\n";
    }
  }
  if (set != nullptr) {
    md += "\n## Measurements\n\n| | training RMS | held-out RMS |\n|---|---|---|\n| prior | " +
          percent(r.train_rms_prior) + " | " + percent(r.held_out_rms_prior) + " |\n| calibrated | " +
          percent(r.train_rms) + " | " + percent(r.held_out_rms) + " |\n\n" + std::to_string(r.held_out_points) +
          " of " + std::to_string(r.operating_points) + " operating points held out; noise estimate " +
          percent(r.noise) + " (" + r.noise_source + ").\n\n";
    for (const std::string& p : plots) md += "![" + p + "](" + p + ")\n";
  }
  if (!r.facts.empty()) {
    md += "\n## Facts\n\n| fact | band | prior | calibrated | holds | every free parameter moving | holds "
          "|\n|---|---|---|---|---|---|---|\n";
    for (const FactOutcome& f : r.facts) {
      md += "| " + f.id + " | " + number(f.min) + " .. " + number(f.max) + " " + f.unit + " | " +
            number(f.prior_value) + " | " + number(f.value) + " | " + (f.holds ? "yes" : "**no**") + " | " +
            number(f.explored_value) + " | " + (f.holds_explored ? "yes" : "**no**") + " |\n";
    }
    if (!r.explored.empty()) {
      md += "\nThe first fit, every free parameter moving (before those the facts do not determine went back to "
            "their priors):";
      for (const auto& [name, value] : r.explored) md += " `" + name + " = " + number(value) + "`";
      md += "\n";
    }
    for (const FactReach& f : r.reach) {
      std::string breaks;
      for (const std::string& b : f.breaks) breaks += (breaks.empty() ? "" : ", ") + b;
      md += "\nPushed to hold (weight 100): **" + f.id + "** " + (f.reachable ? "holds" : "still fails") + " at " +
            number(f.value) +
            (breaks.empty() ? "; nothing else breaks." : "; then these lose (their miss grows): " + breaks + ".");
    }
    for (const FactFront& f : r.fronts) {
      md += "\n\nFront between " + f.first + " and " + f.second +
            " (the optimum as the first one's weight grows):\n\n| weight | " + f.first + " | " + f.second +
            " |\n|---|---|---|\n";
      for (std::size_t k = 0; k < f.weights.size(); ++k) {
        md += "| " + number(f.weights[k], "%g") + " | " + number(f.first_values[k]) + " | " +
              number(f.second_values[k]) + " |\n";
      }
    }
    md += "\n";
  }
  md += "\n" + std::to_string(r.rounds) + " rounds, " + std::to_string(r.starts_run) + " starts, " +
        std::to_string(r.model_evaluations) + " model evaluations, " + number(wall_s, "%.1f") + " s.\n";
  return md;
}

std::string calibration_fitted_header(const std::string& command_line, const CalibrationResult& r) {
  std::string h = "# Written by `swum calibrate " + command_line + "`: " + r.conclusion + "\n";
  for (const CalibratedParameter& p : r.parameters) {
    h += "#   " + p.name + " = " +
         (p.identifiable ? number(p.value) + " +- " + number(p.standard_error, "%.2g") + " " + p.unit + " (prior " +
                               number(p.prior) + ")"
                         : number(p.value) + " " + p.unit + ", not identifiable: " + p.reason) +
         "\n";
  }
  return h;
}

}  // namespace swum::host
