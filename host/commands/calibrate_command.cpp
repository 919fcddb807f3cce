// `swum calibrate`: the model's base parameters fitted to a measured sweep and/or a facts file,
// with standard errors, an identifiability verdict per parameter, a held-out score and the
// trade-offs between facts that cannot all hold (docs/calibration.md).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "analysis/calibration/calibration.h"
#include "analysis/calibration/calibration_candidates.h"
#include "analysis/calibration/calibration_facts.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "commands/config_option.h"
#include "formats/facts_file.h"
#include "formats/name_list.h"
#include "formats/number_format.h"
#include "formats/parameter_file.h"
#include "offline/motor_config.h"
#include "offline/parallel_for.h"
#include "output/reports/fit/calibration_report.h"
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
  double dwell_ms = 1e3 * PredictionOptions::measurement_protocol().window_s;
  bool no_trade_offs = false;
  bool json = false;
  int jobs = 0;
};

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
  if (o.dwell_ms != d.dwell_ms) c += " --dwell-ms " + format_number(o.dwell_ms, "%g");
  if (o.no_trade_offs) c += " --no-trade-offs";
  return c;
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
  if (!(o.dwell_ms >= 1.0 && o.dwell_ms <= 10000.0)) throw std::invalid_argument("--dwell-ms: must be in 1..10000");
  CalibrationOptions options;
  options.prediction.steady.settle_s = 1e-3 * o.settle_ms;
  options.prediction.steady.window_s = 1e-3 * o.dwell_ms;
  options.prediction.steady.max_s = 1e-3 * (o.settle_ms + o.dwell_ms);
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
  const std::string given = command_line(o);
  write_text_file_atomically(out, calibration_fitted_header(given, r) + "\n" + format_motor_parameters(r.fitted));
  const std::string json = calibration_json(r, set != nullptr, wall_s);
  if (!o.report_dir.empty()) {
    const std::vector<std::string> plots = set != nullptr ? write_calibration_plots(o.report_dir, *set, r)
                                                          : std::vector<std::string>{};
    write_text_file_atomically(fs::path(o.report_dir) / "report.md",
                               calibration_report_markdown(given, set, r, plots, wall_s));
    write_text_file_atomically(fs::path(o.report_dir) / "summary.json", json);
  }
  if (o.json) {
    std::fputs(json.c_str(), stdout);
  } else {
    std::fputs(calibration_summary_text(r, set != nullptr).c_str(), stdout);
    std::printf("wrote %s%s (%.1f s, %d model evaluations)\n", o.out_path.c_str(),
                o.report_dir.empty() ? "" : (" and " + o.report_dir + "/report.md").c_str(), wall_s,
                r.model_evaluations);
  }
}

}  // namespace

void add_calibrate_command(CLI::App& app) {
  auto o = std::make_shared<CalibrateCommandOptions>();
  CLI::App* sub = app.add_subcommand("calibrate", "Fit the model's base parameters to a measured sweep or to facts");
  add_config_option(*sub, o->config_path, "prior motor parameter file (TOML)");
  sub->add_option(
      "--measured", o->measured_path,
      "CSV as swum sweep / swum log write it (amplitude_v,frequency_hz,load_n + speed_mm_s and/or tip amplitudes)");
  sub->add_option("--facts", o->facts_path, "facts file (TOML, [[fact]] tables; docs/calibration.md)");
  sub->add_option("--free", o->free, "parameters to fit, comma list of section.key (default: chosen from the data)");
  sub->add_option("--candidates", o->candidates, "pool the free set is chosen from (default: every candidate)");
  sub->add_option("--max-free", o->max_free, "largest free set chosen")->capture_default_str();
  sub->add_option("--starts", o->starts, "starts of the first fit (the prior, then seeded random)")
      ->capture_default_str();
  sub->add_option("--max-evaluations", o->max_evaluations, "with --facts: cost evaluations per fit")
      ->capture_default_str();
  sub->add_option("--settle-ms", o->settle_ms,
                  "with --measured: each predicted point settles this long (ms; match the sweep's --settle-ms)")
      ->capture_default_str();
  sub->add_option("--dwell-ms", o->dwell_ms,
                  "with --measured: and is averaged over this window (ms; match the sweep's --dwell-ms)")
      ->capture_default_str();
  sub->add_flag("--no-trade-offs", o->no_trade_offs, "with --facts: do not push failing facts or trace fronts");
  sub->add_option("--out", o->out_path, "fitted parameter file (TOML)")->required();
  sub->add_option("--report", o->report_dir, "directory for report.md, summary.json and plots");
  sub->add_flag("--json", o->json, "print one JSON object instead of the text summary");
  sub->add_option("--jobs", o->jobs, "worker threads (default: all cores)");
  sub->callback([o] { run_calibrate_command(*o); });
}

}  // namespace swum::host
