// `swum size [--config F] --amplitude-v LIST [--load LIST] [--temperature-rise-k LIST]`: what an
// amplifier board must deliver over an envelope (docs/sizing.md): `swum band`'s rows with the
// electrical port read along every down-sweep, the figures of each phase at the drift-aware
// operating point, their worst cases and where, and the matching network sized at the design row
// (src/analysis/sizing/amplifier_sizing.h); rows to --out (CSV), the sizing as --json or text, and
// a report folder (--report: report.md, plots, summary.json).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/operating_point/operating_point.h"
#include "analysis/sizing/amplifier_sizing.h"
#include "analysis/sizing/series_in_loop.h"
#include "analysis/studies/population.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "commands/config_option.h"
#include "commands/envelope_options.h"
#include "formats/spread_file.h"
#include "offline/band_run.h"
#include "offline/motor_config.h"
#include "offline/parallel_for.h"
#include "output/progress_bar.h"
#include "output/reports/operating_point/size_report.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

namespace fs = std::filesystem;

struct SizeOptions {
  std::string config_path;
  EnvelopeOptions envelope;
  std::string out_path;
  std::string report_dir;
  bool json = false;
  int jobs = 0;
  std::string spreads_path;  // a population: motors drawn as `swum population` draws them
  std::uint64_t motors = 100;
  std::uint64_t seed = 1;
  double yield = 0.95;
  double source_resistance_ohm = 5.0;  // the amplifier's output resistance for the series design in the loop
  bool motors_given = false, seed_given = false, yield_given = false;
  std::string command_line;
};

constexpr std::uint64_t kMaxMotors = 100000;

// Each motor of the population over the same envelope, with the nominal motor's network.
std::vector<SizingResult> size_motors(const SizeOptions& o, const MotorParameters& nominal,
                                      const std::vector<ParameterSpread>& spreads, const BandGrid& grid,
                                      const SizingResult& nominal_sizing) {
  std::vector<SizingResult> motors(o.motors);
  ProgressBar progress("motors", o.motors);
  std::mutex progress_mutex;
  // Motors on the threads, each motor's chains in the lanes of its thread: a motor's few chains
  // would not fill the threads themselves. The figures depend on neither.
  make_parallel_for(static_cast<unsigned>(o.jobs))(o.motors, [&](std::size_t i) {
    const MotorParameters drawn = with_drawn_values(nominal, spreads, draw_spread_values(spreads, o.seed, i));
    bool valid = true;
    try {
      validate_parameters(drawn, "motor " + std::to_string(i));
    } catch (const std::exception&) {
      valid = false;  // a rejected draw: no rows, never within the figures
    }
    if (valid) {
      const MotorModel model(drawn);
      motors[i] = size_amplifier_with_network(run_operating_band(model, grid, 1), nominal_sizing.design_a,
                                              nominal_sizing.design_b);
    }
    const std::lock_guard lock(progress_mutex);
    progress.advance();
  });
  return motors;
}

void run_size(const SizeOptions& o) {
  const BandGrid grid = envelope_grid(o.envelope, o.jobs);  // every bad value named before the file is read
  if (!(o.yield > 0.0 && o.yield <= 1.0)) throw std::invalid_argument("--yield: must be within (0, 1]");
  if (o.spreads_path.empty() && (o.motors_given || o.seed_given || o.yield_given)) {
    throw std::invalid_argument(std::string(o.motors_given ? "--motors"
                                            : o.seed_given ? "--seed"
                                                           : "--yield") +
                                ": describes a population and needs --spreads");
  }
  if (o.motors < 1 || o.motors > kMaxMotors) throw std::invalid_argument("--motors: must be within 1..100000");
  if (!(o.source_resistance_ohm > 0.0 && o.source_resistance_ohm <= 1000.0)) {
    throw std::invalid_argument("--source-resistance-ohm: must be within (0, 1000] ohm");
  }
  if (grid.frequencies_hz.size() < 3) {
    throw CommandError("--frequency-hz: " + o.envelope.frequency_range +
                       " has fewer than 3 points: the operating point needs a curve through the peak");
  }
  // Where the outputs go is checked before the sweeps, which can take minutes with --spreads.
  if (!o.report_dir.empty()) {
    std::error_code ec;
    fs::create_directories(o.report_dir, ec);
    if (ec) throw CommandError("cannot create report directory " + o.report_dir + ": " + ec.message());
  }
  if (!o.out_path.empty()) {
    const fs::path parent = fs::path(o.out_path).parent_path();
    if (!parent.empty() && !fs::is_directory(parent)) {
      throw CommandError("--out: cannot write " + o.out_path + ": " + parent.string() + " is not a directory");
    }
  }
  const MotorParameters parameters = load_motor_parameters(o.config_path);
  check_band_thermal(grid, parameters, o.config_path);
  const AmplifierParameters& network = parameters.amplifier;
  if (network.source_resistance_ohm != 0.0 || network.series_inductance_uh != 0.0 ||
      network.parallel_inductance_uh != 0.0) {
    throw CommandError(o.config_path +
                       ": [amplifier] sets an output network; swum size sizes one for an ideal source and reads "
                       "--amplitude-v at the terminals: remove the section (docs/sizing.md)");
  }
  std::vector<ParameterSpread> spreads;  // read before the sweeps, which take minutes with a population
  if (!o.spreads_path.empty()) {
    spreads = parse_parameter_spreads(read_text_file(o.spreads_path), o.spreads_path, parameters);
  }
  const MotorModel model(parameters);
  std::vector<BandRow> rows;
  {
    ProgressBar progress("size", grid.voltages.size() * grid.loads_n.size() * grid.temperature_rises_k.size() *
                                     grid.frequencies_hz.size());
    rows = run_operating_band(model, grid, o.jobs, [&] { progress.advance(); });
  }
  const double c0_f = parameters.stator.clamped_capacitance_nf * 1e-9;
  const SizingResult sizing = size_amplifier(rows, c0_f, default_design_row(rows));
  std::optional<SeriesInLoop> series;
  if (sizing.designed && sizing.design_a.series_ok) {
    const SizingRow& d = sizing.rows[sizing.design_row];
    series = series_matching_in_loop(parameters, d.frequency_hz, d.a.voltage_v, d.a.admittance_siemens,
                                     o.source_resistance_ohm);
  }
  std::vector<SizingResult> motors;
  std::optional<PopulationSizing> population;
  if (!o.spreads_path.empty()) {
    motors = size_motors(o, parameters, spreads, grid, sizing);
    std::vector<const SizingResult*> pointers;
    for (const SizingResult& m : motors) pointers.push_back(m.rows.empty() ? nullptr : &m);
    population = size_population(pointers, o.yield);
  }
  SizeContext context;
  context.config_path = o.config_path;
  context.command = o.command_line;
  context.margin_hz = o.envelope.margin_hz;
  context.clamped_capacitance_f = c0_f;
  context.spreads_path = o.spreads_path;
  context.seed = o.seed;
  context.population = population;
  context.series_in_loop = series;
  if (!o.out_path.empty()) write_text_file_atomically(o.out_path, size_csv(sizing));
  if (!o.report_dir.empty()) {
    const std::vector<std::string> plots = write_size_plots(o.report_dir, rows, sizing);
    write_text_file_atomically(fs::path(o.report_dir) / "report.md", size_markdown(sizing, context, plots));
    write_text_file_atomically(fs::path(o.report_dir) / "summary.json", size_json(sizing, context));
  }
  const std::string text = o.json ? size_json(sizing, context) : size_text(sizing, context, o.out_path);
  std::fputs(text.c_str(), stdout);
  if (population && !(population->oscillator_reached && population->current_rms_a.reached)) {
    throw CommandError("the yield is not reached: fewer than " + std::to_string(population->needed) + " of " +
                       std::to_string(population->motors) + " motors were sized at every row");
  }
  const std::size_t unsized = sizing.rows.size() - sizing.summary.sized;
  if (unsized > 0) {
    throw CommandError(std::to_string(unsized) + " of " + std::to_string(sizing.rows.size()) +
                       " rows not sized: the figures may not cover them (see reason)");
  }
}

}  // namespace

void add_size_command(CLI::App& app) {
  auto o = std::make_shared<SizeOptions>();
  CLI::App* sub = app.add_subcommand(
      "size", "Amplifier sizing over voltages, loads and stator temperatures: currents, power, matching network");
  add_config_option(*sub, o->config_path, "motor parameter file (TOML)");
  add_envelope_options(*sub, o->envelope);
  sub->add_option("--out", o->out_path, "write the rows as CSV (atomically)");
  sub->add_option("--report", o->report_dir, "directory for report.md, summary.json and plots");
  sub->add_flag("--json", o->json, "the sizing as JSON on stdout");
  sub->add_option("--source-resistance-ohm", o->source_resistance_ohm,
                  "the amplifier's output resistance for the series design sized in the loop (ohm, (0, 1000])")
      ->capture_default_str();
  sub->add_option("--spreads", o->spreads_path,
                  "spreads file (as swum population): also size a population of motors with the nominal network");
  sub->add_option("--motors", o->motors, "motors to draw with --spreads (1..100000)")->capture_default_str();
  sub->add_option("--seed", o->seed, "study seed with --spreads: motor i's parameters depend on (seed, i) only")
      ->capture_default_str();
  sub->add_option("--yield", o->yield, "share of the motors the figures must cover with --spreads, (0, 1]")
      ->capture_default_str();
  sub->add_option("--jobs", o->jobs, "worker threads (0: all cores)")->capture_default_str();
  sub->callback([o, sub] {
    o->motors_given = sub->count("--motors") > 0;
    o->seed_given = sub->count("--seed") > 0;
    o->yield_given = sub->count("--yield") > 0;
    o->command_line = "swum size";
    for (const CLI::Option* option : sub->get_options()) {
      if (option->count() == 0 || option->get_name() == "--help") continue;
      o->command_line += " " + option->get_name();
      if (option->get_expected_min() == 0) continue;  // a flag: its name says it all
      for (const std::string& value : option->results()) o->command_line += " " + value;
    }
    run_size(*o);
  });
}

}  // namespace swum::host
