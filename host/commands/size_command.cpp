// `swum size [--config F] --amplitude-v LIST [--load LIST] [--temperature-rise-k LIST]`: what an
// amplifier board must deliver over an envelope (docs/sizing.md): `swum band`'s rows with the
// electrical port read along every down-sweep, the figures of each phase at the drift-aware
// operating point, their worst cases and where, and the matching network sized at the design row
// (src/analysis/sizing/amplifier_sizing.h); rows to --out (CSV), the sizing as --json or text, and
// a report folder (--report: report.md, plots, summary.json).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "analysis/operating_point/operating_point.h"
#include "analysis/sizing/amplifier_sizing.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "commands/config_option.h"
#include "offline/band_run.h"
#include "offline/motor_config.h"
#include "output/progress_bar.h"
#include "output/reports/operating_point/size_report.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

namespace fs = std::filesystem;

struct SizeOptions {
  std::string config_path;
  std::string amplitude_v_list;
  std::string load_list = "0";
  std::string rise_list = "0";
  double margin_hz = kDefaultMarginHz;
  std::string frequency_range = kDefaultFrequencyGrid;
  std::string out_path;
  std::string report_dir;
  bool json = false;
  int jobs = 0;
  std::string command_line;
};

void run_size(const SizeOptions& o) {
  BandGrid grid;
  grid.voltages = parse_number_list(o.amplitude_v_list, "--amplitude-v");
  grid.loads_n = parse_number_list(o.load_list, "--load");
  grid.temperature_rises_k = parse_number_list(o.rise_list, "--temperature-rise-k");
  grid.frequencies_hz = parse_range_or_value(o.frequency_range, "--frequency-hz");
  grid.margin_hz = o.margin_hz;
  check_band_grid(grid, o.jobs);  // every bad value named before the file is read
  if (grid.frequencies_hz.size() < 3) {
    throw CommandError("--frequency-hz: " + o.frequency_range +
                       " has fewer than 3 points: the operating point needs a curve through the peak");
  }
  const MotorParameters parameters = load_motor_parameters(o.config_path);
  check_band_thermal(grid, parameters, o.config_path);
  const MotorModel model(parameters);
  std::vector<BandRow> rows;
  {
    ProgressBar progress("size", grid.voltages.size() * grid.loads_n.size() * grid.temperature_rises_k.size() *
                                     grid.frequencies_hz.size());
    rows = run_operating_band(model, grid, o.jobs, [&] { progress.advance(); });
  }
  const double c0_f = parameters.stator.clamped_capacitance_nf * 1e-9;
  const SizingResult sizing = size_amplifier(rows, c0_f, default_design_row(rows));
  SizeContext context;
  context.config_path = o.config_path;
  context.command = o.command_line;
  context.margin_hz = o.margin_hz;
  context.clamped_capacitance_f = c0_f;
  if (!o.out_path.empty()) write_text_file_atomically(o.out_path, size_csv(sizing));
  if (!o.report_dir.empty()) {
    std::error_code ec;
    fs::create_directories(o.report_dir, ec);
    if (ec) throw CommandError("cannot create report directory " + o.report_dir + ": " + ec.message());
    const std::vector<std::string> plots = write_size_plots(o.report_dir, rows, sizing);
    write_text_file_atomically(fs::path(o.report_dir) / "report.md", size_markdown(sizing, context, plots));
    write_text_file_atomically(fs::path(o.report_dir) / "summary.json", size_json(sizing, context));
  }
  const std::string text = o.json ? size_json(sizing, context) : size_text(sizing, context, o.out_path);
  std::fputs(text.c_str(), stdout);
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
  sub->add_option("--amplitude-v", o->amplitude_v_list,
                  "terminal voltage amplitudes per phase, comma list (V, zero-to-peak)")
      ->required();
  sub->add_option("--load", o->load_list, "loads, comma list (N)")->capture_default_str();
  sub->add_option("--temperature-rise-k", o->rise_list,
                  "stator temperature rises over ambient, comma list (K, 0..300; other than 0 needs [effects.thermal])")
      ->capture_default_str();
  sub->add_option("--margin-hz", o->margin_hz, "minimum margin above the peak (Hz), as swum pick and swum band")
      ->capture_default_str();
  sub->add_option("--frequency-hz", o->frequency_range,
                  "START:STOP:STEP (Hz); every chain runs it from STOP down to START (default: 41500 down to 38000 Hz "
                  "in 25 Hz steps)")
      ->capture_default_str();
  sub->add_option("--out", o->out_path, "write the rows as CSV (atomically)");
  sub->add_option("--report", o->report_dir, "directory for report.md, summary.json and plots");
  sub->add_flag("--json", o->json, "the sizing as JSON on stdout");
  sub->add_option("--jobs", o->jobs, "worker threads (0: all cores)")->capture_default_str();
  sub->callback([o, sub] {
    o->command_line = "swum size";
    for (const CLI::Option* option : sub->get_options()) {
      if (option->count() == 0 || option->get_name() == "--help") continue;
      o->command_line += " " + option->get_name();
      for (const std::string& value : option->results()) o->command_line += " " + value;
    }
    run_size(*o);
  });
}

}  // namespace swum::host
