// `swum identify`: the four non-linear constants from measured free-stator tip amplitudes
// (paper Sec. 4, model_spec §6.5). Writes a new parameter file; the input config is not touched.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "analysis/identification/identification.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "commands/config_option.h"
#include "formats/parameter_file.h"
#include "model/motor_model.h"
#include "offline/motor_config.h"
#include "output/amplitude_csv.h"
#include "output/reports/model/identification_report.h"
#include "output/text_files.h"

namespace swum::host {
namespace {

namespace fs = std::filesystem;

struct IdentifyOptions {
  std::string config_path;
  std::string amplitudes_path;
  std::string out_path;
  std::string report_dir;
  bool json = false;
  int starts = IdentificationOptions{}.starts;
  std::uint64_t seed = IdentificationOptions{}.seed;
};

std::string fitted_file_text(const IdentifyOptions& o, const MotorParameters& fitted, const IdentificationResult& r) {
  return identification_fitted_header("--config " + o.config_path + " --amplitudes " + o.amplitudes_path, r) +
         format_motor_parameters(fitted);
}

void write_report(const IdentifyOptions& o, const MotorModel& fitted_model,
                  const std::vector<AmplitudeMeasurement>& data, const IdentificationResult& r) {
  const fs::path dir(o.report_dir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw CommandError("cannot create report directory " + dir.string() + ": " + ec.message());
  write_identification_plots(dir, fitted_model, data);
  write_text_file_atomically(dir / "residuals.csv", identification_residuals_csv(r));
  write_text_file_atomically(dir / "summary.json", identification_json(r));
  write_text_file_atomically(dir / "summary.txt", identification_summary_text(r));
}

bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

void run_identify(const IdentifyOptions& o) {
  if (same_file(o.out_path, o.config_path)) {
    throw std::invalid_argument("--out: " + o.out_path + " is the input config; the input is never overwritten");
  }
  if (o.starts < 1) throw std::invalid_argument("--starts: must be >= 1");
  const MotorParameters prior = load_motor_parameters(o.config_path);
  const std::vector<AmplitudeMeasurement> data = parse_amplitude_csv(read_text_file(o.amplitudes_path),
                                                                     o.amplitudes_path, kNonlinearParameterCount);
  IdentificationOptions options;
  options.starts = o.starts;
  options.seed = o.seed;
  const IdentificationResult r = identify_nonlinear_parameters(prior, data, options);
  if (!r.ok) throw CommandError("identification failed: " + r.failure);

  MotorParameters fitted = prior;
  fitted.stator = r.fitted_stator;
  write_text_file_atomically(o.out_path, fitted_file_text(o, fitted, r));
  if (!o.report_dir.empty()) write_report(o, MotorModel(fitted), data, r);
  if (o.json) {
    std::fputs(identification_json(r).c_str(), stdout);
  } else {
    std::fputs(identification_summary_text(r).c_str(), stdout);
    std::printf("wrote %s%s\n", o.out_path.c_str(),
                o.report_dir.empty() ? "" : (" and the report in " + o.report_dir).c_str());
  }
}

}  // namespace

void add_identify_command(CLI::App& app) {
  auto o = std::make_shared<IdentifyOptions>();
  CLI::App* sub = app.add_subcommand("identify", "Fit c111, c1111, e311, e3111 to measured free-stator tip amplitudes");
  add_config_option(*sub, o->config_path, "prior motor parameter file (TOML, not modified)");
  sub->add_option("--amplitudes", o->amplitudes_path,
                  "CSV: amplitude_v,frequency_hz,tip_normal_um,tip_tangential_um (amplitude cells may be empty)")
      ->required();
  sub->add_option("--out", o->out_path, "fitted parameter file to write (TOML)")->required();
  sub->add_option("--report", o->report_dir,
                  "directory for fit_normal.png, fit_tangential.png, residuals.csv, summary.*");
  sub->add_flag("--json", o->json, "print one JSON object instead of the table");
  sub->add_option("--starts", o->starts, "least-squares starts per fit")->capture_default_str();
  sub->add_option("--seed", o->seed, "seed of the random starts")->capture_default_str();
  sub->callback([o] { run_identify(*o); });
}

}  // namespace swum::host
