// `swum calibrate`: the model's base parameters fitted to a measured sweep and/or a facts file,
// with standard errors, an identifiability verdict per parameter, a held-out score and the
// trade-offs between facts that cannot all hold (docs/calibration.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <system_error>
#include <tuple>
#include <vector>

#include "analysis/calibration/calibration.h"
#include "analysis/calibration/calibration_candidates.h"
#include "analysis/calibration/calibration_facts.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "formats/facts_file.h"
#include "formats/name_list.h"
#include "formats/number_format.h"
#include "formats/parameter_file.h"
#include "offline/motor_config.h"
#include "offline/parallel_for.h"
#include "output/plot.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

namespace fs = std::filesystem;

struct CalibrateCommandOptions {
  std::string config_path;
  std::string measured_path;
  std::string facts_path;
  std::string free;
  std::string candidates;
  std::string out_path;
  std::string report_dir;
  int max_free = CalibrationOptions{}.max_free;
  int starts = CalibrationOptions{}.starts;
  int max_evaluations = CalibrationOptions{}.max_evaluations;
  // The measurement protocol of each predicted point (PredictionOptions::measurement_protocol).
  double settle_ms = 1e3 * PredictionOptions::measurement_protocol().settle_s;
  double window_ms = 1e3 * PredictionOptions::measurement_protocol().window_s;
  bool no_trade_offs = false;
  bool json = false;
  int jobs = 0;
};

std::string number(double v, const char* format = "%.6g") {
  if (std::isfinite(v)) return format_number(v, format);
  return std::isnan(v) ? "n/a" : (v > 0.0 ? "inf" : "-inf");
}
std::string percent(double v) { return format_number(100.0 * v, "%.3g") + " %"; }

nlohmann::ordered_json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr; }

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
    char line[512];
    if (p.identifiable) {
      std::snprintf(line, sizeof line, "  %-34s %-12s +- %-9s %s (prior %s)%s\n", p.name.c_str(),
                    number(p.value).c_str(), number(p.standard_error, "%.2g").c_str(), p.unit.c_str(),
                    number(p.prior).c_str(), p.at_bound ? "  AT A BOUND" : "");
    } else {
      std::snprintf(line, sizeof line, "  %-34s not identifiable: %s\n", p.name.c_str(), p.reason.c_str());
    }
    out += line;
  }
  return out;
}

std::string summary_text(const CalibrationResult& r, bool measured) {
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
std::vector<std::string> write_plots(const fs::path& dir, const MeasurementSet& set, const CalibrationResult& r) {
  std::vector<std::string> files;
  std::set<double> loads;
  for (const Measurement& m : set.rows) loads.insert(m.load_n);
  for (Quantity q : kQuantities) {
    const auto qi = static_cast<std::size_t>(q);
    if (!set.has_quantity[qi]) continue;
    for (double load : loads) {
      std::map<double, std::vector<std::size_t>> by_vpp;
      for (std::size_t i = 0; i < set.rows.size(); ++i) {
        if (set.rows[i].load_n == load && set.rows[i].value(q)) by_vpp[set.rows[i].vpp].push_back(i);
      }
      if (by_vpp.empty()) continue;
      PlotSpec spec;
      spec.title = "Measured (points) vs prior (dashed) and calibrated (line), load " + number(load, "%g") + " N";
      spec.x_label = "frequency (Hz)";
      spec.y_label = std::string(quantity_label(q));
      for (auto& [vpp, rows] : by_vpp) {
        std::sort(rows.begin(), rows.end(),
                  [&](std::size_t a, std::size_t b) { return set.rows[a].frequency_hz < set.rows[b].frequency_hz; });
        const std::string v = number(vpp, "%g") + " Vpp";
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

// The options that shape the result, as given (the output paths and --json/--jobs left out).
std::string command_line(const CalibrateCommandOptions& o) {
  const CalibrateCommandOptions d;
  std::string c = "--config " + o.config_path;
  if (!o.measured_path.empty()) c += " --measured " + o.measured_path;
  if (!o.facts_path.empty()) c += " --facts " + o.facts_path;
  if (!o.free.empty()) c += " --free " + o.free;
  if (!o.candidates.empty()) c += " --candidates " + o.candidates;
  if (o.max_free != d.max_free) c += " --max-free " + std::to_string(o.max_free);
  if (o.starts != d.starts) c += " --starts " + std::to_string(o.starts);
  if (!o.facts_path.empty() && o.max_evaluations != d.max_evaluations) {
    c += " --max-evaluations " + std::to_string(o.max_evaluations);
  }
  if (o.settle_ms != d.settle_ms) c += " --settle-ms " + format_number(o.settle_ms, "%g");
  if (o.window_ms != d.window_ms) c += " --window-ms " + format_number(o.window_ms, "%g");
  if (o.no_trade_offs) c += " --no-trade-offs";
  return c;
}

std::string report_markdown(const CalibrateCommandOptions& o, const MeasurementSet* set, const CalibrationResult& r,
                            const std::vector<std::string>& plots, double wall_s) {
  std::string md = "# Calibration report\n\n`swum calibrate " + command_line(o) + "`\n\n**Conclusion:** " +
                   r.conclusion + "\n\n";
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

std::string fitted_header(const CalibrateCommandOptions& o, const CalibrationResult& r) {
  std::string h = "# Written by `swum calibrate " + command_line(o) + "`: " + r.conclusion + "\n";
  for (const CalibratedParameter& p : r.parameters) {
    h += "#   " + p.name + " = " +
         (p.identifiable ? number(p.value) + " +- " + number(p.standard_error, "%.2g") + " " + p.unit + " (prior " +
                               number(p.prior) + ")"
                         : number(p.value) + " " + p.unit + ", not identifiable: " + p.reason) +
         "\n";
  }
  return h;
}

void run_calibrate_command(const CalibrateCommandOptions& o) {
  if (o.jobs < 0) throw std::invalid_argument("--jobs: must be >= 1 (0 = all cores)");
  if (o.measured_path.empty() && o.facts_path.empty()) {
    throw std::invalid_argument("give --measured (a sweep) and/or --facts (a facts file)");
  }
  if (o.max_free < 1) throw std::invalid_argument("--max-free: must be >= 1");
  if (o.starts < 1) throw std::invalid_argument("--starts: must be >= 1");
  if (o.max_evaluations < 10) throw std::invalid_argument("--max-evaluations: must be >= 10");
  if (!(o.settle_ms >= 0.0 && o.settle_ms <= 10000.0)) throw std::invalid_argument("--settle-ms: must be in 0..10000");
  if (!(o.window_ms >= 1.0 && o.window_ms <= 10000.0)) throw std::invalid_argument("--window-ms: must be in 1..10000");
  CalibrationOptions options;
  options.prediction.steady.settle_s = 1e-3 * o.settle_ms;
  options.prediction.steady.window_s = 1e-3 * o.window_ms;
  options.prediction.steady.max_s = 1e-3 * (o.settle_ms + o.window_ms);
  options.max_free = o.max_free;
  options.starts = o.starts;
  options.max_evaluations = o.max_evaluations;
  options.trade_offs = !o.no_trade_offs;
  if (!o.free.empty()) options.free = parse_name_list(o.free, "--free");
  if (!o.candidates.empty()) options.candidates = parse_name_list(o.candidates, "--candidates");
  if (!options.free.empty() && !options.candidates.empty()) {
    throw std::invalid_argument("--free and --candidates: give one (--free fixes the set, --candidates is the pool)");
  }
  const MotorParameters prior = load_motor_parameters(o.config_path);
  for (const auto* list : {&options.free, &options.candidates}) {
    for (const std::string& name : *list) {
      if (std::count(list->begin(), list->end(), name) > 1) {
        throw std::invalid_argument(std::string(list == &options.free ? "--free" : "--candidates") + ": '" + name +
                                    "' is listed twice");
      }
      const CalibrationCandidate* c = find_calibration_candidate(name);
      if (c == nullptr) {
        throw std::invalid_argument(std::string(list == &options.free ? "--free" : "--candidates") + ": '" + name +
                                    "' is not a parameter calibration can fit (" + calibration_candidate_names() + ")");
      }
      try {
        (void)calibration_free_parameter(*c, prior);  // throws when it does not apply to this motor
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(list == &options.free ? "--free: " : "--candidates: ") + e.what());
      }
    }
  }
  std::optional<MeasurementSet> measured;
  if (!o.measured_path.empty()) {
    try {
      measured = parse_measurements_csv(read_text_file(o.measured_path), o.measured_path);
    } catch (const MeasurementError& e) {
      throw CommandError(e.what());
    }
    if (const std::string note = measurement_note(*measured); !note.empty()) {
      std::fprintf(stderr, "%s: %s\n", o.measured_path.c_str(), note.c_str());
    }
    constexpr std::size_t kMinOperatingPoints = 8;
    if (count_operating_points(*measured) < kMinOperatingPoints) {
      throw CommandError(o.measured_path + ": " + std::to_string(count_operating_points(*measured)) +
                         " distinct operating points; calibration needs at least " +
                         std::to_string(kMinOperatingPoints) + " (a quarter, at least 4, are held out)");
    }
    options.split.min_points = 4;
  }
  std::vector<Fact> facts;
  if (!o.facts_path.empty()) {
    try {
      facts = parse_facts(read_text_file(o.facts_path), o.facts_path);
    } catch (const ParameterError& e) {
      throw CommandError(e.what());
    }
  }
  // The outputs' places first: a bad path must not fail after minutes of fitting.
  const fs::path out(o.out_path);
  if (o.out_path.empty() || fs::is_directory(out)) throw CommandError("--out: '" + o.out_path + "' is not a file name");
  if (out.has_parent_path() && !fs::is_directory(out.parent_path())) {
    throw CommandError("--out: no directory " + out.parent_path().string());
  }
  if (!o.report_dir.empty()) {
    std::error_code ec;
    fs::create_directories(o.report_dir, ec);
    if (ec) throw CommandError("cannot create report directory " + o.report_dir + ": " + ec.message());
  }

  const auto start = std::chrono::steady_clock::now();
  const ParallelFor parallel = make_parallel_for(static_cast<unsigned>(o.jobs));
  const MeasurementSet* set = measured ? &*measured : nullptr;
  const CalibrationResult r = facts.empty() ? calibrate_to_measurements(prior, *measured, options, parallel)
                                            : calibrate_to_facts(prior, facts, set, options, parallel);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  write_text_file_atomically(out, fitted_header(o, r) + "\n" + format_motor_parameters(r.fitted));
  const nlohmann::ordered_json j = to_json(r, set != nullptr, wall_s);
  if (!o.report_dir.empty()) {
    const std::vector<std::string> plots = set != nullptr ? write_plots(o.report_dir, *set, r)
                                                          : std::vector<std::string>{};
    write_text_file_atomically(fs::path(o.report_dir) / "report.md", report_markdown(o, set, r, plots, wall_s));
    write_text_file_atomically(fs::path(o.report_dir) / "summary.json", j.dump(2) + "\n");
  }
  if (o.json) {
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::fputs(summary_text(r, set != nullptr).c_str(), stdout);
    std::printf("wrote %s%s (%.1f s, %d model evaluations)\n", o.out_path.c_str(),
                o.report_dir.empty() ? "" : (" and " + o.report_dir + "/report.md").c_str(), wall_s,
                r.model_evaluations);
  }
}

}  // namespace

void add_calibrate_command(CLI::App& app) {
  auto o = std::make_shared<CalibrateCommandOptions>();
  CLI::App* sub = app.add_subcommand("calibrate", "Fit the model's base parameters to a measured sweep or to facts");
  sub->add_option("--config", o->config_path, "prior motor parameter file (TOML)")->required();
  sub->add_option("--measured", o->measured_path,
                  "CSV as swum sweep / swum log write it (vpp,frequency_hz,load_n + speed_mm_s and/or tip amplitudes)");
  sub->add_option("--facts", o->facts_path, "facts file (TOML, [[fact]] tables; docs/calibration.md)");
  sub->add_option("--free", o->free, "parameters to fit, comma list of section.key (default: chosen from the data)");
  sub->add_option("--candidates", o->candidates, "pool the free set is chosen from (default: every candidate)");
  sub->add_option("--max-free", o->max_free, "largest free set chosen")->capture_default_str();
  sub->add_option("--starts", o->starts, "starts of the first fit (the prior, then seeded random)")
      ->capture_default_str();
  sub->add_option("--max-evaluations", o->max_evaluations, "with --facts: cost evaluations per fit")
      ->capture_default_str();
  sub->add_option("--settle-ms", o->settle_ms,
                  "with --measured: each predicted point settles this long (match the sweep's --settle-ms)")
      ->capture_default_str();
  sub->add_option("--window-ms", o->window_ms,
                  "with --measured: and is averaged over this window (match the sweep's --dwell-ms)")
      ->capture_default_str();
  sub->add_flag("--no-trade-offs", o->no_trade_offs, "with --facts: do not push failing facts or trace fronts");
  sub->add_option("--out", o->out_path, "fitted parameter file (TOML)")->required();
  sub->add_option("--report", o->report_dir, "directory for report.md, summary.json and plots");
  sub->add_flag("--json", o->json, "print one JSON object instead of the text summary");
  sub->add_option("--jobs", o->jobs, "worker threads (default: all cores)");
  sub->callback([o] { run_calibrate_command(*o); });
}

}  // namespace swum::host
