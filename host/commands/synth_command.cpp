// `swum synth`: measurement-like data from any config with any candidate effect enabled
// (docs/discrepancy.md), so anyone can test the discrepancy workflow on a known hidden effect.
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/discrepancy/candidate_effects.h"
#include "analysis/measurements/synthetic_measurements.h"
#include "commands/commands.h"
#include "commands/config_option.h"
#include "formats/name_list.h"
#include "formats/parameter_edit.h"
#include "offline/motor_config.h"
#include "offline/parallel_for.h"
#include "output/partial_file.h"
#include "output/text_files.h"

namespace swum::host {
namespace {

struct SynthCommandOptions {
  std::string config_path;
  std::vector<std::string> effects;
  std::string points_path;
  double noise = 0.02;
  std::uint64_t seed = 1;
  std::string out_path;
  bool linear = false;
  int repeats = 1;
  int jobs = 0;
  double speed_floor_mm_s = 0.0;
  double amplitude_floor_um = 0.0;
  double frequency_jitter_hz = 0.0;
  std::vector<std::string> quantities;        // comma lists, as given (repeatable); none: all three
  std::vector<std::string> sets;              // --set SECTION.KEY=VALUE, as given (repeatable)
  std::vector<std::string> scales;            // --scale SECTION.KEY=FACTOR, as given (repeatable)
  std::vector<ParameterEditKind> edit_order;  // which of the two each --set/--scale was, in command-line order
};

// The --set and --scale items in command-line order, parsed (parse_parameter_edit's one-line
// errors) before any work.
std::vector<ParameterEdit> parameter_edits(const SynthCommandOptions& o) {
  std::vector<ParameterEdit> edits;
  std::size_t next_set = 0, next_scale = 0;
  for (const ParameterEditKind kind : o.edit_order) {
    const bool set = kind == ParameterEditKind::set;
    edits.push_back(parse_parameter_edit(kind, set ? o.sets.at(next_set++) : o.scales.at(next_scale++)));
  }
  return edits;
}

// "speed, tip_normal" -> which quantity columns to write (parse_name_list: an empty name is
// refused, blanks around a name dropped, as `swum discrepancy --quantities`).
std::array<bool, kQuantityCount> quantity_selection(const std::vector<std::string>& lists) {
  if (lists.empty()) return {true, true, true};
  std::vector<std::string> names;
  for (const std::string& list : lists) {
    for (std::string& name : parse_name_list(list, "--quantities")) names.push_back(std::move(name));
  }
  std::array<bool, kQuantityCount> chosen{};
  for (const std::string& name : names) {
    const std::optional<Quantity> q = quantity_from_name(name);
    if (!q) {
      throw std::invalid_argument("--quantities: unknown quantity '" + name +
                                  "' (known: speed, tip_normal, tip_tangential)");
    }
    chosen[static_cast<std::size_t>(*q)] = true;
  }
  return chosen;
}

void run_synth(const SynthCommandOptions& o) {
  if (!(o.noise >= 0.0 && o.noise < 1.0)) {
    throw std::invalid_argument("--noise: relative noise must be within [0, 1), got " + std::to_string(o.noise));
  }
  if (o.repeats < 1 || o.repeats > 1000) throw std::invalid_argument("--repeats: must be 1..1000");
  if (o.jobs < 0) throw std::invalid_argument("--jobs: must be >= 1 (0 = all cores)");
  if (!(o.speed_floor_mm_s >= 0.0 && o.speed_floor_mm_s <= 1000.0)) {
    throw std::invalid_argument("--speed-floor-mm-s: must be within 0..1000");
  }
  if (!(o.amplitude_floor_um >= 0.0 && o.amplitude_floor_um <= 10.0)) {
    throw std::invalid_argument("--amplitude-floor-um: must be within 0..10");
  }
  if (!(o.frequency_jitter_hz >= 0.0 && o.frequency_jitter_hz <= 1000.0)) {
    throw std::invalid_argument("--frequency-jitter-hz: must be within 0..1000");
  }
  const std::array<bool, kQuantityCount> quantities = quantity_selection(o.quantities);
  const std::vector<ParameterEdit> edits = parameter_edits(o);
  // The order of docs/discrepancy.md: the config, --linear, --set/--scale as given, --effect.
  MotorParameters parameters = load_motor_parameters(o.config_path);
  if (o.linear) parameters = linearised(parameters);
  for (const ParameterEdit& edit : edits) apply_parameter_edit(parameters, edit);
  if (!edits.empty()) {
    try {
      validate_parameters(parameters, "--set/--scale");  // what one key's range cannot say (half height < length)
    } catch (const ParameterError& e) {
      throw std::invalid_argument(e.what());
    }
  }
  for (const std::string& effect : o.effects) {
    try {
      apply_effect_argument(parameters, effect);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--effect: ") + e.what());
    }
  }
  validate_parameters(parameters, "--effect");
  const MeasurementSet points = parse_operating_points_csv(read_text_file(o.points_path), o.points_path);
  SynthOptions options;
  options.relative_noise = o.noise;
  options.seed = o.seed;
  options.repeats = o.repeats;
  options.speed_floor_mm_s = o.speed_floor_mm_s;
  options.amplitude_floor_um = o.amplitude_floor_um;
  options.frequency_jitter_hz = o.frequency_jitter_hz;
  options.quantities = quantities;
  std::string header = "# swum synth --config " + o.config_path + (o.linear ? " --linear" : "");
  for (const ParameterEdit& edit : edits) {
    header += " " + std::string(parameter_edit_option(edit.kind)) + " " + edit.text;
  }
  for (const std::string& e : o.effects) header += " --effect " + e;
  header += " --noise " + std::to_string(o.noise) + " --seed " + std::to_string(o.seed);
  header += " --speed-floor-mm-s " + std::to_string(o.speed_floor_mm_s) + " --amplitude-floor-um " +
            std::to_string(o.amplitude_floor_um) + " --frequency-jitter-hz " + std::to_string(o.frequency_jitter_hz) +
            "\n";
  // Rows go to OUT.partial as they are final (a killed run leaves whole rows), OUT at the end.
  const MeasurementSet layout = synthesis_layout(points.rows, options);
  PartialFile file(o.out_path, header + format_measurements_header(layout));
  const MeasurementSet data = synthesize_measurements(
      parameters, points.rows, options, make_parallel_for(static_cast<unsigned>(o.jobs)),
      [&](const Measurement& row) { file.append(format_measurement_row(layout, row)); });
  file.commit();
  const std::size_t dropped = points.rows.size() * static_cast<std::size_t>(o.repeats) - data.rows.size();
  std::printf("wrote %zu rows to %s%s\n", data.rows.size(), o.out_path.c_str(),
              dropped > 0 ? (" (" + std::to_string(dropped) + " diverged readings left out)").c_str() : "");
}

}  // namespace

void add_synth_command(CLI::App& app) {
  auto o = std::make_shared<SynthCommandOptions>();
  CLI::App* sub = app.add_subcommand("synth", "Measurement-like data from a config with hidden effects, with noise");
  add_config_option(*sub, o->config_path, "motor parameter file (TOML)");
  sub->add_option("--effect", o->effects,
                  "NAME or NAME:key=value,... (repeatable): electroelastic, thermal, wear, "
                  "preload, guide_friction, amplifier_droop");
  CLI::Option* set = sub->add_option("--set", o->sets,
                                     "SECTION.KEY=VALUE (repeatable): a parameter of the config replaced, e.g. "
                                     "contact.preload_n=26 (keys: docs/parameters.md)");
  CLI::Option* scale = sub->add_option("--scale", o->scales,
                                       "SECTION.KEY=FACTOR (repeatable): a parameter of the config multiplied, e.g. "
                                       "stator.damping_l1_n_s_m=1.4; --set and --scale apply in command-line order, "
                                       "after --linear, before --effect");
  sub->add_option("--points", o->points_path,
                  "CSV of operating points: amplitude_v,frequency_hz,load_n[,time_s][,sweep]")
      ->required();
  sub->add_option("--noise", o->noise, "relative Gaussian noise (multiplicative)")->capture_default_str();
  sub->add_option("--seed", o->seed, "noise seed")->capture_default_str();
  sub->add_option("--out", o->out_path, "measurements CSV to write")->required();
  sub->add_flag("--linear", o->linear, "zero c111, c1111, e311, e3111 of the config first");
  sub->add_option("--repeats", o->repeats, "readings per point")->capture_default_str();
  sub->add_option("--jobs", o->jobs, "worker threads (default: all cores)");
  sub->add_option("--speed-floor-mm-s", o->speed_floor_mm_s,
                  "additive speed noise (standard deviation, mm/s): the sensor's floor")
      ->capture_default_str();
  sub->add_option("--amplitude-floor-um", o->amplitude_floor_um,
                  "additive tip-amplitude noise (standard deviation, um)")
      ->capture_default_str();
  sub->add_option("--frequency-jitter-hz", o->frequency_jitter_hz,
                  "drive frequency error per reading (standard deviation, Hz)")
      ->capture_default_str();
  sub->add_option("--quantities", o->quantities,
                  "columns to write, comma list of speed, tip_normal, tip_tangential (default: all)");
  sub->callback([o, sub, set, scale] {
    // CLI11 keeps each option's values apart; the order of the two comes from the parse order
    // (one entry per value).
    o->edit_order.clear();
    for (const CLI::Option* option : sub->parse_order()) {
      if (option == set) o->edit_order.push_back(ParameterEditKind::set);
      if (option == scale) o->edit_order.push_back(ParameterEditKind::scale);
    }
    run_synth(*o);
  });
}

}  // namespace swum::host
