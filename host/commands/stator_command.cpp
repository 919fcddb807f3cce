// `swum stator`: harmonic balance of the free stator (paper Sec. 4, eqs. 26-32;
// model_spec §6.2-6.3) over voltages x frequencies: every real branch with its stability, and
// the backbone.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/free_stator/harmonic_balance.h"
#include "commands/commands.h"
#include "commands/config_option.h"
#include "offline/motor_config.h"
#include "output/reports/model/stator_report.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

struct StatorOptions {
  std::string config_path;
  std::string amplitude_v_list;
  std::string frequency_range;
  bool json = false;
  std::string out_path;
  std::string plot_path;
  std::string backbone_path;
};

std::filesystem::path sibling(const std::filesystem::path& path, const std::string& suffix) {
  std::filesystem::path p = path;
  p.replace_filename(path.stem().string() + suffix + path.extension().string());
  return p;
}

void run_stator(const StatorOptions& o) {
  const std::vector<double> voltages = parse_number_list(o.amplitude_v_list, "--amplitude-v");
  const std::vector<double> frequencies = parse_range_or_value(o.frequency_range, "--frequency-hz");
  for (double v : voltages) {
    if (v < 0.0) throw std::invalid_argument("--amplitude-v: voltages must be >= 0");
  }
  for (double f : frequencies) {
    if (f < 1000.0 || f > 200000.0) {
      throw std::invalid_argument("--frequency-hz: must be within 1000..200000 Hz");
    }
  }
  const MotorModel model(load_motor_parameters(o.config_path));
  const FreeStatorHarmonicBalance hb(model);

  std::vector<SweepPoint> sweep;
  if (frequencies.size() > 1 || voltages.size() == 1) {
    for (double v : voltages) {
      auto part = sweep_frequency(hb, v, frequencies);
      sweep.insert(sweep.end(), part.begin(), part.end());
    }
  } else {
    sweep = sweep_voltage(hb, frequencies.front(), voltages);
  }
  const std::vector<StatorRow> rows = stator_rows(sweep);

  std::vector<BackbonePoint> backbone;
  if (o.json || !o.backbone_path.empty() || !o.plot_path.empty()) {
    for (double v : voltages) backbone.push_back(hb.backbone(v));
  }
  if (o.json) {
    std::fputs(stator_json(rows, backbone).c_str(), stdout);
  } else if (!o.out_path.empty()) {
    write_text_file_atomically(o.out_path, stator_csv(rows));
  } else {
    std::fputs(stator_csv(rows).c_str(), stdout);
  }
  if (!o.backbone_path.empty()) {
    write_text_file_atomically(o.backbone_path, stator_backbone_csv(backbone));
  }
  if (!o.plot_path.empty()) {
    const std::filesystem::path plot(o.plot_path);
    write_stator_plot(sweep, voltages, frequencies, backbone, StatorMode::b2, plot);
    write_stator_plot(sweep, voltages, frequencies, backbone, StatorMode::l1, sibling(plot, "_normal"));
  }
}

}  // namespace

void add_stator_command(CLI::App& app) {
  auto o = std::make_shared<StatorOptions>();
  CLI::App* sub = app.add_subcommand(
      "stator", "Free-stator tip amplitudes by harmonic balance: all branches, stability, backbone");
  add_config_option(*sub, o->config_path, "motor parameter file (TOML)");
  sub->add_option("--amplitude-v", o->amplitude_v_list,
                  "terminal voltage amplitudes per phase, comma list (V, zero-to-peak)")
      ->required();
  sub->add_option("--frequency-hz", o->frequency_range, "START:STOP:STEP or one value (Hz)")->required();
  auto* json = sub->add_flag("--json", o->json, "print one JSON object (rows and backbone)");
  auto* out = sub->add_option("--out", o->out_path,
                              "output CSV (default: stdout) with columns "
                              "amplitude_v,frequency_hz,branch,stable,tip_normal_um,tip_tangential_um");
  json->excludes(out);
  sub->add_option("--plot", o->plot_path, "PNG of the tangential amplitude (and <name>_normal.png of the normal one)");
  sub->add_option("--backbone", o->backbone_path, "CSV of the peak frequency and amplitude of each mode per voltage");
  sub->callback([o] { run_stator(*o); });
}

}  // namespace swum::host
