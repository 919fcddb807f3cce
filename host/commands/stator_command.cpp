// `swum stator`: harmonic balance of the free stator (paper Sec. 4, eqs. 26-32;
// model_spec §6.2-6.3) over voltages x frequencies: every real branch with its stability, and
// the backbone.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/free_stator/harmonic_balance.h"
#include "commands/commands.h"
#include "formats/number_format.h"
#include "offline/motor_config.h"
#include "output/plot.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

struct StatorOptions {
  std::string config_path;
  std::string vpp_list;
  std::string frequency_range;
  bool json = false;
  std::string out_path;
  std::string plot_path;
  std::string backbone_path;
};

// One state of the free stator: one branch of each (independent) mode.
struct StatorRow {
  double vpp = 0.0;
  double frequency_hz = 0.0;
  int branch = 0;  // index over the product of the two modes' branches (descending amplitude)
  int normal_branch = 0;
  int tangential_branch = 0;
  bool normal_stable = false;
  bool tangential_stable = false;
  bool followed = false;  // the state an up-sweep in frequency follows
  double tip_normal_um = 0.0;
  double tip_tangential_um = 0.0;
  bool stable() const { return normal_stable && tangential_stable; }
};

std::vector<StatorRow> rows_of(const std::vector<SweepPoint>& sweep) {
  std::vector<StatorRow> rows;
  for (const SweepPoint& p : sweep) {
    const auto& n = p.response.normal.branches;
    const auto& t = p.response.tangential.branches;
    int branch = 0;
    for (std::size_t i = 0; i < n.size(); ++i) {
      for (std::size_t k = 0; k < t.size(); ++k) {
        StatorRow row;
        row.vpp = p.response.vpp;
        row.frequency_hz = p.response.frequency_hz;
        row.branch = branch++;
        row.normal_branch = static_cast<int>(i);
        row.tangential_branch = static_cast<int>(k);
        row.normal_stable = n[i].stable;
        row.tangential_stable = t[k].stable;
        row.followed = static_cast<int>(i) == p.followed_normal && static_cast<int>(k) == p.followed_tangential;
        row.tip_normal_um = n[i].tip_amplitude_um;
        row.tip_tangential_um = t[k].tip_amplitude_um;
        rows.push_back(row);
      }
    }
  }
  return rows;
}

std::string format_csv(const std::vector<StatorRow>& rows) {
  std::string out = "vpp,frequency_hz,branch,stable,tip_normal_um,tip_tangential_um\n";
  char line[256];
  for (const StatorRow& r : rows) {
    std::snprintf(line, sizeof line, "%.10g,%.10g,%d,%d,%.6f,%.6f\n", r.vpp, r.frequency_hz, r.branch,
                  r.stable() ? 1 : 0, r.tip_normal_um, r.tip_tangential_um);
    out += line;
  }
  return out;
}

std::string format_backbone_csv(const std::vector<BackbonePoint>& backbone) {
  std::string out = "vpp,normal_peak_hz,normal_peak_um,tangential_peak_hz,tangential_peak_um\n";
  char line[256];
  for (const BackbonePoint& b : backbone) {
    std::snprintf(line, sizeof line, "%.10g,%.3f,%.6f,%.3f,%.6f\n", b.vpp, b.normal_peak_hz, b.normal_peak_um,
                  b.tangential_peak_hz, b.tangential_peak_um);
    out += line;
  }
  return out;
}

nlohmann::ordered_json to_json(const std::vector<StatorRow>& rows, const std::vector<BackbonePoint>& backbone) {
  nlohmann::ordered_json j;
  j["rows"] = nlohmann::ordered_json::array();
  for (const StatorRow& r : rows) {
    j["rows"].push_back({{"vpp", r.vpp},
                         {"frequency_hz", r.frequency_hz},
                         {"branch", r.branch},
                         {"stable", r.stable()},
                         {"tip_normal_um", r.tip_normal_um},
                         {"tip_tangential_um", r.tip_tangential_um},
                         {"normal_branch", r.normal_branch},
                         {"tangential_branch", r.tangential_branch},
                         {"normal_stable", r.normal_stable},
                         {"tangential_stable", r.tangential_stable},
                         {"followed_by_up_sweep", r.followed}});
  }
  j["backbone"] = nlohmann::ordered_json::array();
  for (const BackbonePoint& b : backbone) {
    j["backbone"].push_back({{"vpp", b.vpp},
                             {"normal_peak_hz", b.normal_peak_hz},
                             {"normal_peak_um", b.normal_peak_um},
                             {"tangential_peak_hz", b.tangential_peak_hz},
                             {"tangential_peak_um", b.tangential_peak_um}});
  }
  return j;
}

std::string vpp_label(double vpp) { return format_number(vpp, "%g") + " Vpp"; }

// Amplitude vs frequency (several frequencies) or vs voltage (one frequency): stable and
// unstable branches as separate series; the backbone (peak frequency) as a line.
void write_plot(const std::vector<SweepPoint>& sweep, const std::vector<double>& voltages,
                const std::vector<double>& frequencies, const std::vector<BackbonePoint>& backbone, StatorMode mode,
                const std::filesystem::path& path) {
  const bool vs_frequency = frequencies.size() > 1;
  const char* axis = mode == StatorMode::l1 ? "normal" : "tangential";
  PlotSpec spec;
  spec.title = std::string("Free stator, tip ") + axis + " amplitude (harmonic balance)";
  spec.x_label = vs_frequency ? "frequency (kHz)" : "voltage (Vpp)";
  spec.y_label = std::string("tip ") + axis + " amplitude (um)";
  auto branches_of = [&](const SweepPoint& p) -> const ModeResponse& { return p.response.mode(mode); };
  auto add_series = [&](const std::string& label, auto&& select, bool stable) {
    PlotSeries s;
    s.label = label;
    s.draw_line = false;  // branches may be multi-valued: markers only
    for (const SweepPoint& p : sweep) {
      if (!select(p)) continue;
      for (const ModeBranch& b : branches_of(p).branches) {
        if (b.stable != stable) continue;
        s.x.push_back(vs_frequency ? p.response.frequency_hz * 1e-3 : p.response.vpp);
        s.y.push_back(b.tip_amplitude_um);
      }
    }
    if (!s.x.empty()) spec.series.push_back(std::move(s));
  };
  if (vs_frequency) {
    for (double v : voltages) {
      add_series(
          vpp_label(v), [v](const SweepPoint& p) { return p.response.vpp == v; }, true);
    }
    add_series(
        "unstable branches", [](const SweepPoint&) { return true; }, false);
    PlotSeries bb;
    bb.label = "backbone (peak)";
    for (const BackbonePoint& b : backbone) {
      bb.x.push_back((mode == StatorMode::l1 ? b.normal_peak_hz : b.tangential_peak_hz) * 1e-3);
      bb.y.push_back(mode == StatorMode::l1 ? b.normal_peak_um : b.tangential_peak_um);
    }
    if (!bb.x.empty()) spec.series.push_back(std::move(bb));
  } else {
    auto all = [](const SweepPoint&) { return true; };
    const std::string khz = format_number(frequencies.front() * 1e-3, "%.1f") + " kHz";
    add_series(khz + " stable", all, true);
    add_series(khz + " unstable", all, false);
  }
  write_png_plot(spec, path);
}

std::filesystem::path sibling(const std::filesystem::path& path, const std::string& suffix) {
  std::filesystem::path p = path;
  p.replace_filename(path.stem().string() + suffix + path.extension().string());
  return p;
}

void run_stator(const StatorOptions& o) {
  const std::vector<double> voltages = parse_number_list(o.vpp_list, "--vpp");
  const std::vector<double> frequencies = parse_range_or_value(o.frequency_range, "--frequency");
  for (double v : voltages) {
    if (v < 0.0) throw std::invalid_argument("--vpp: voltages must be >= 0");
  }
  for (double f : frequencies) {
    if (f < 1000.0 || f > 200000.0) {
      throw std::invalid_argument("--frequency: must be within 1000..200000 Hz");
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
  const std::vector<StatorRow> rows = rows_of(sweep);

  std::vector<BackbonePoint> backbone;
  if (o.json || !o.backbone_path.empty() || !o.plot_path.empty()) {
    for (double v : voltages) backbone.push_back(hb.backbone(v));
  }
  if (o.json) {
    std::printf("%s\n", to_json(rows, backbone).dump(2).c_str());
  } else if (!o.out_path.empty()) {
    write_text_file_atomically(o.out_path, format_csv(rows));
  } else {
    std::fputs(format_csv(rows).c_str(), stdout);
  }
  if (!o.backbone_path.empty()) {
    write_text_file_atomically(o.backbone_path, format_backbone_csv(backbone));
  }
  if (!o.plot_path.empty()) {
    const std::filesystem::path plot(o.plot_path);
    write_plot(sweep, voltages, frequencies, backbone, StatorMode::b2, plot);
    write_plot(sweep, voltages, frequencies, backbone, StatorMode::l1, sibling(plot, "_normal"));
  }
}

}  // namespace

void add_stator_command(CLI::App& app) {
  auto o = std::make_shared<StatorOptions>();
  CLI::App* sub = app.add_subcommand(
      "stator", "Free-stator tip amplitudes by harmonic balance: all branches, stability, backbone");
  sub->add_option("--config", o->config_path, "motor parameter file (TOML)")->required();
  sub->add_option("--vpp", o->vpp_list, "drive voltages, comma list (V peak-to-peak)")->required();
  sub->add_option("--frequency", o->frequency_range, "START:STOP:STEP or one value (Hz)")->required();
  auto* json = sub->add_flag("--json", o->json, "print one JSON object (rows and backbone)");
  auto* out = sub->add_option("--out", o->out_path,
                              "output CSV (default: stdout) with columns "
                              "vpp,frequency_hz,branch,stable,tip_normal_um,tip_tangential_um");
  json->excludes(out);
  sub->add_option("--plot", o->plot_path, "PNG of the tangential amplitude (and <name>_normal.png of the normal one)");
  sub->add_option("--backbone", o->backbone_path, "CSV of the peak frequency and amplitude of each mode per voltage");
  sub->callback([o] { run_stator(*o); });
}

}  // namespace swum::host
