// `swum discrepancy`: where the model and measurements disagree, which candidate effect
// explains it, the augmented config and the gap before -> after (docs/discrepancy.md).
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "analysis/discrepancy/discrepancy.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "commands/config_option.h"
#include "formats/name_list.h"
#include "formats/parameter_file.h"
#include "offline/motor_config.h"
#include "offline/parallel_for.h"
#include "output/reports/fit/discrepancy_report.h"
#include "output/text_files.h"

namespace swum::host {
namespace {

namespace fs = std::filesystem;

struct DiscrepancyCommandOptions {
  std::string config_path;
  std::string measured_path;
  std::string out_dir;
  std::string effects;
  std::optional<std::string> quantities;  // comma list; absent: every quantity column of the file
  std::string discovery = "on";
  std::string groups;
  bool json = false;
  int jobs = 0;
};

// --quantities: analyse only these columns (e.g. speed, as a board without a vibrometer
// measures); rows left without a value are dropped.
void keep_quantities(MeasurementSet& set, const std::vector<std::string>& names) {
  std::array<bool, kQuantityCount> keep{};
  for (const std::string& name : names) {
    const std::optional<Quantity> q = quantity_from_name(name);
    if (!q) {
      throw std::invalid_argument("--quantities: unknown quantity '" + name +
                                  "' (known: speed, tip_normal, tip_tangential)");
    }
    keep[static_cast<std::size_t>(*q)] = true;
  }
  for (Quantity q : kQuantities) {
    const auto j = static_cast<std::size_t>(q);
    if (keep[j] && !set.has_quantity[j]) {
      throw std::invalid_argument("--quantities: the file has no " + std::string(quantity_column(q)) + " column");
    }
    set.has_quantity[j] = set.has_quantity[j] && keep[j];
    if (!keep[j]) {
      for (Measurement& m : set.rows) m.values[j].reset();
    }
  }
  std::erase_if(set.rows, [](const Measurement& m) {
    return std::none_of(m.values.begin(), m.values.end(), [](const auto& v) { return v.has_value(); });
  });
}

void run_discrepancy_command(const DiscrepancyCommandOptions& o) {
  if (o.jobs < 0) throw std::invalid_argument("--jobs: must be >= 1 (0 = all cores)");
  DiscrepancyOptions options;
  if (!o.effects.empty()) options.candidates = parse_name_list(o.effects, "--effects");
  for (const std::string& name : options.candidates) {
    if (find_candidate_effect(name) == nullptr) {
      throw std::invalid_argument("--effects: unknown effect '" + name + "' (known: " + candidate_effect_names() + ")");
    }
  }
  if (o.discovery != "on" && o.discovery != "off") {
    throw std::invalid_argument("--discovery: must be on or off, got '" + o.discovery + "'");
  }
  options.discovery.enabled = o.discovery == "on";
  if (!o.groups.empty()) {
    if (!options.discovery.enabled) throw std::invalid_argument("--groups: needs --discovery on");
    options.discovery.groups = parse_name_list(o.groups, "--groups");
  }
  const MotorParameters baseline = load_motor_parameters(o.config_path);
  try {
    validate_discovery_groups(options.discovery, baseline);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--groups: ") + e.what());
  }
  MeasurementSet measured;
  try {
    measured = parse_measurements_csv(read_text_file(o.measured_path), o.measured_path);
  } catch (const MeasurementError& e) {
    throw CommandError(e.what());
  }
  if (const std::string note = measurement_note(measured); !note.empty()) {
    std::fprintf(stderr, "%s: %s\n", o.measured_path.c_str(), note.c_str());
  }
  if (o.quantities) keep_quantities(measured, parse_name_list(*o.quantities, "--quantities"));
  // A quarter of the operating points (at least 12, at most half) are held out for scoring. The
  // smallest combined held-out p is 2 x 2^-m for m held-out points: below 16 points (8 held
  // out) no effect could ever reach 0.01, so such a file cannot say anything either way.
  constexpr std::size_t kMinOperatingPoints = 16;
  const std::size_t operating_points = count_operating_points(measured);
  if (operating_points < kMinOperatingPoints) {
    throw CommandError(o.measured_path + ": " + std::to_string(operating_points) +
                       " distinct operating points; the workflow needs at least " +
                       std::to_string(kMinOperatingPoints) +
                       " (8 held out, the fewest whose held-out tests can reach p < 0.01)");
  }
  // The output directory first: a bad path must not fail after a minute of fitting.
  const fs::path dir(o.out_dir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw CommandError("cannot create output directory " + dir.string() + ": " + ec.message());

  const auto start = std::chrono::steady_clock::now();
  const DiscrepancyResult r = run_discrepancy(baseline, measured, options,
                                              make_parallel_for(static_cast<unsigned>(o.jobs)));
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string inputs = "--config " + o.config_path + " --measured " + o.measured_path;
  write_text_file_atomically(dir / "augmented.toml",
                             discrepancy_augmented_header(inputs, r) + "\n" + format_motor_parameters(r.augmented));
  const std::vector<std::string> plots = write_discrepancy_plots(dir, measured, r);
  write_text_file_atomically(dir / "report.md", discrepancy_report_markdown(inputs, measured, r, plots));
  const std::string json = discrepancy_json(r, wall_s);
  write_text_file_atomically(dir / "summary.json", json);
  if (o.json) {
    std::fputs(json.c_str(), stdout);
  } else {
    std::fputs(discrepancy_summary_text(r).c_str(), stdout);
    std::printf("wrote %s/report.md, augmented.toml and %zu plots (%.1f s, %d model evaluations)\n", o.out_dir.c_str(),
                plots.size(), wall_s, r.model_evaluations);
  }
}

}  // namespace

void add_discrepancy_command(CLI::App& app) {
  auto o = std::make_shared<DiscrepancyCommandOptions>();
  CLI::App* sub = app.add_subcommand("discrepancy",
                                     "Name the effect missing from a model, add it, show the gap shrink");
  add_config_option(*sub, o->config_path, "baseline motor parameter file (TOML)");
  sub->add_option(
         "--measured", o->measured_path,
         "CSV: amplitude_v,frequency_hz,load_n[,time_s][,sweep] + speed_mm_s/tip_normal_um/tip_tangential_um; or a "
         "swum sweep / swum log file as it is")
      ->required();
  sub->add_option("--out", o->out_dir, "directory for report.md, plots, augmented.toml")->required();
  sub->add_option("--effects", o->effects, "candidate effects, comma list (default: all)");
  sub->add_option(
      "--quantities", o->quantities,
      "measured columns to use, comma list of speed, tip_normal, tip_tangential (default: all in the file)");
  sub->add_option("--discovery", o->discovery,
                  "after the library, search changes of the base model (groups of base parameters): on or off")
      ->capture_default_str();
  sub->add_option("--groups", o->groups,
                  "groups of base parameters the discovery may change, comma list (default: every group that applies; "
                  "docs/discrepancy.md)");
  sub->add_flag("--json", o->json, "print one JSON object instead of the text summary");
  sub->add_option("--jobs", o->jobs, "worker threads (default: all cores)");
  sub->callback([o] { run_discrepancy_command(*o); });
}

}  // namespace swum::host
