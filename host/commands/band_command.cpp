// `swum band --config F --amplitude-v LIST [--load LIST] [--temperature-rise-k LIST]`: the band of drive
// frequencies an amplifier's oscillator must cover, from the model: a continuous down-sweep per
// (voltage, load, stator temperature rise), the drift-aware pick on each
// (src/analysis/operating_point/operating_band.h); rows to --out (CSV, written atomically) or
// --json, the band on stdout (docs/host.md).
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "analysis/operating_point/operating_point.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "commands/config_option.h"
#include "commands/envelope_options.h"
#include "offline/band_run.h"
#include "offline/motor_config.h"
#include "output/progress_bar.h"
#include "output/reports/operating_point/band_report.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

struct BandOptions {
  std::string config_path;
  EnvelopeOptions envelope;
  std::string out_path;
  bool json = false;
  int jobs = 0;
};

void run_band(const BandOptions& o) {
  const BandGrid grid = envelope_grid(o.envelope, o.jobs);  // every bad value named before the file is read
  const MotorParameters parameters = load_motor_parameters(o.config_path);
  check_band_thermal(grid, parameters, o.config_path);
  const MotorModel model(parameters);
  std::vector<BandRow> rows;
  {
    ProgressBar progress("band", grid.voltages.size() * grid.loads_n.size() * grid.temperature_rises_k.size() *
                                     grid.frequencies_hz.size());
    rows = run_operating_band(model, grid, o.jobs, [&] { progress.advance(); });
  }
  const BandSummary summary = summarize_band(rows);
  if (!o.out_path.empty()) write_text_file_atomically(o.out_path, band_csv(rows));
  const std::string text = o.json ? band_json(rows, summary, o.envelope.margin_hz)
                                  : band_text(rows, summary, o.envelope.margin_hz, o.out_path);
  std::fputs(text.c_str(), stdout);
  if (summary.undecided > 0) {
    throw CommandError(std::to_string(summary.undecided) + " of " + std::to_string(rows.size()) +
                       " rows undecided: the band may not cover them (see reason)");
  }
}

}  // namespace

void add_band_command(CLI::App& app) {
  auto o = std::make_shared<BandOptions>();
  CLI::App* sub = app.add_subcommand(
      "band", "Band of operating frequencies over voltages, loads and stator temperatures (model down-sweeps)");
  add_config_option(*sub, o->config_path, "motor parameter file (TOML)");
  add_envelope_options(*sub, o->envelope);
  sub->add_option("--out", o->out_path, "write the rows as CSV (atomically), with the electrical port at each pick");
  sub->add_flag("--json", o->json, "summary and rows as JSON on stdout");
  sub->add_option("--jobs", o->jobs, "worker threads (0: all cores)")->capture_default_str();
  sub->callback([o] { run_band(*o); });
}

}  // namespace swum::host
