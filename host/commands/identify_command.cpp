// `swum identify`: the four non-linear constants from measured free-stator tip amplitudes
// (paper Sec. 4, model_spec §6.5). Writes a new parameter file; the input config is not touched.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>
#include <vector>

#include "analysis/identification/identification.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "formats/number_format.h"
#include "formats/parameter_file.h"
#include "model/motor_model.h"
#include "offline/motor_config.h"
#include "output/amplitude_csv.h"
#include "output/plot.h"
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

nlohmann::ordered_json to_json(const IdentificationResult& r) {
  nlohmann::ordered_json j;
  j["parameters"] = nlohmann::ordered_json::array();
  for (const ParameterEstimate& e : r.parameters) {
    nlohmann::ordered_json p;
    p["key"] = std::string(e.key);
    p["identifiable"] = e.identifiable;
    p["value"] = e.value;  // the fitted value, or the prior when not identifiable
    p["prior"] = e.prior;
    p["standard_error"] = e.identifiable ? nlohmann::ordered_json(e.standard_error) : nlohmann::ordered_json(nullptr);
    p["significant"] = e.significant;
    p["reason"] = e.reason;
    j["parameters"].push_back(p);
  }
  j["rms_relative_residual"] = r.rms_relative_residual;
  j["rms_normal_um"] = std::isfinite(r.rms_normal_um) ? nlohmann::ordered_json(r.rms_normal_um)
                                                      : nlohmann::ordered_json(nullptr);
  j["rms_tangential_um"] = std::isfinite(r.rms_tangential_um) ? nlohmann::ordered_json(r.rms_tangential_um)
                                                              : nlohmann::ordered_json(nullptr);
  j["amplitude_count"] = r.residual_count;
  j["information_eigenvalues"] = r.information_eigenvalues;
  j["starts"] = r.starts_run;
  j["rounds"] = r.rounds;
  return j;
}

std::string summary_text(const IdentificationResult& r) {
  std::string out = "parameter          value          std. error   status\n";
  for (const ParameterEstimate& e : r.parameters) {
    char line[512];
    if (e.identifiable) {
      std::snprintf(line, sizeof line, "%-18s %-14s %-12s identified%s\n", std::string(e.key).c_str(),
                    format_number(e.value, "%+.5g").c_str(), format_number(e.standard_error, "%.2g").c_str(),
                    e.significant ? ", significantly non-zero" : ", NOT significantly non-zero");
    } else {
      std::snprintf(line, sizeof line, "%-18s %-14s %-12s not identifiable, kept at prior: %s\n",
                    std::string(e.key).c_str(), format_number(e.prior, "%+.5g").c_str(), "-", e.reason.c_str());
    }
    out += line;
  }
  out += "RMS residual: " + format_number(100.0 * r.rms_relative_residual, "%.3g") + " % (relative)";
  if (std::isfinite(r.rms_normal_um)) out += ", normal " + format_number(r.rms_normal_um, "%.3g") + " um";
  if (std::isfinite(r.rms_tangential_um)) {
    out += ", tangential " + format_number(r.rms_tangential_um, "%.3g") + " um";
  }
  out += " over " + std::to_string(r.residual_count) + " amplitudes\n";
  return out;
}

std::string fitted_file_text(const IdentifyOptions& o, const MotorParameters& fitted, const IdentificationResult& r) {
  std::string header = "# Written by `swum identify --config " + o.config_path + " --amplitudes " + o.amplitudes_path +
                       "`.\n# Non-linear constants (paper Sec. 4, docs/model_spec.md §6.5):\n";
  for (const ParameterEstimate& e : r.parameters) {
    header += "#   " + std::string(e.key) + " = " + format_number(e.value, "%.6g");
    header += e.identifiable ? " +- " + format_number(e.standard_error, "%.2g") + " (fitted)"
                             : " (prior kept: not identifiable by these data)";
    header += "\n";
  }
  header += "#   RMS relative residual " + format_number(100.0 * r.rms_relative_residual, "%.3g") + " % over " +
            std::to_string(r.residual_count) + " amplitudes\n\n";
  return header + format_motor_parameters(fitted);
}

// Data against fitted curves, one PNG per axis (paper Figs. 7-8): per frequency, the fitted
// amplitude along a voltage up-sweep (the branch it follows) and the measured points.
void write_report(const IdentifyOptions& o, const MotorModel& fitted_model,
                  const std::vector<AmplitudeMeasurement>& data, const IdentificationResult& r) {
  const fs::path dir(o.report_dir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw CommandError("cannot create report directory " + dir.string() + ": " + ec.message());
  std::map<double, std::vector<const AmplitudeMeasurement*>> by_frequency;
  double v_max = 0.0;
  for (const AmplitudeMeasurement& m : data) {
    by_frequency[m.frequency_hz].push_back(&m);
    v_max = std::max(v_max, m.vpp);
  }
  std::vector<double> grid;
  for (int i = 0; i <= 80; ++i) grid.push_back(v_max * i / 80.0);
  const FreeStatorHarmonicBalance hb(fitted_model);
  for (StatorMode mode : {StatorMode::l1, StatorMode::b2}) {
    const bool normal = mode == StatorMode::l1;
    PlotSpec spec;
    spec.title = std::string("Identification: tip ") + (normal ? "normal" : "tangential") + " amplitude, data and fit";
    spec.x_label = "voltage (Vpp)";
    spec.y_label = std::string("tip ") + (normal ? "normal" : "tangential") + " amplitude (um)";
    for (const auto& [f, points] : by_frequency) {
      PlotSeries measured;
      measured.label = format_number(f * 1e-3, "%.2f") + " kHz data";
      measured.draw_line = false;
      for (const AmplitudeMeasurement* m : points) {
        const auto& a = normal ? m->tip_normal_um : m->tip_tangential_um;
        if (!a) continue;
        measured.x.push_back(m->vpp);
        measured.y.push_back(*a);
      }
      if (measured.x.empty()) continue;
      PlotSeries fit;
      fit.label = format_number(f * 1e-3, "%.2f") + " kHz fit";
      fit.draw_markers = false;
      for (const SweepPoint& p : sweep_voltage(hb, f, grid)) {
        const int k = normal ? p.followed_normal : p.followed_tangential;
        if (k < 0) continue;
        fit.x.push_back(p.response.vpp);
        fit.y.push_back(p.response.mode(mode).branches[k].tip_amplitude_um);
      }
      spec.series.push_back(std::move(measured));
      if (!fit.x.empty()) spec.series.push_back(std::move(fit));
    }
    if (!spec.series.empty()) {
      write_png_plot(spec, dir / (normal ? "fit_normal.png" : "fit_tangential.png"));
    }
  }
  std::string csv = "vpp,frequency_hz,tip_normal_um,fit_normal_um,tip_tangential_um,fit_tangential_um\n";
  auto cell = [](const std::optional<double>& v) { return v ? format_number(*v, "%.6g") : std::string(); };
  for (const PointPrediction& p : r.predictions) {
    csv += format_number(p.measurement.vpp, "%.10g") + "," + format_number(p.measurement.frequency_hz, "%.10g") + "," +
           cell(p.measurement.tip_normal_um) + "," + cell(p.predicted_normal_um) + "," +
           cell(p.measurement.tip_tangential_um) + "," + cell(p.predicted_tangential_um) + "\n";
  }
  write_text_file_atomically(dir / "residuals.csv", csv);
  write_text_file_atomically(dir / "summary.json", to_json(r).dump(2) + "\n");
  write_text_file_atomically(dir / "summary.txt", summary_text(r));
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
    std::printf("%s\n", to_json(r).dump(2).c_str());
  } else {
    std::fputs(summary_text(r).c_str(), stdout);
    std::printf("wrote %s%s\n", o.out_path.c_str(),
                o.report_dir.empty() ? "" : (" and the report in " + o.report_dir).c_str());
  }
}

}  // namespace

void add_identify_command(CLI::App& app) {
  auto o = std::make_shared<IdentifyOptions>();
  CLI::App* sub = app.add_subcommand("identify", "Fit c111, c1111, e311, e3111 to measured free-stator tip amplitudes");
  sub->add_option("--config", o->config_path, "prior motor parameter file (TOML, not modified)")->required();
  sub->add_option("--amplitudes", o->amplitudes_path,
                  "CSV: vpp,frequency_hz,tip_normal_um,tip_tangential_um (amplitude cells may be empty)")
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
