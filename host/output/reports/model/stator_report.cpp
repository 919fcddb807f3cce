#include "output/reports/model/stator_report.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "formats/number_format.h"
#include "output/plot.h"
#include "output/reports/report_values.h"

namespace swum::host {

std::vector<StatorRow> stator_rows(const std::vector<SweepPoint>& sweep) {
  std::vector<StatorRow> rows;
  for (const SweepPoint& p : sweep) {
    const auto& n = p.response.normal.branches;
    const auto& t = p.response.tangential.branches;
    int branch = 0;
    for (std::size_t i = 0; i < n.size(); ++i) {
      for (std::size_t k = 0; k < t.size(); ++k) {
        StatorRow row;
        row.amplitude_v = p.response.amplitude_v;
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

std::string stator_csv(const std::vector<StatorRow>& rows) {
  std::string out = "amplitude_v,frequency_hz,branch,stable,tip_normal_um,tip_tangential_um\n";
  std::string line;
  for (const StatorRow& r : rows) {
    line = printf_string("%.10g,%.10g,%d,%d,%.6f,%.6f\n", r.amplitude_v, r.frequency_hz, r.branch, r.stable() ? 1 : 0,
                         r.tip_normal_um, r.tip_tangential_um);
    out += line;
  }
  return out;
}

std::string stator_backbone_csv(const std::vector<BackbonePoint>& backbone) {
  std::string out = "amplitude_v,normal_peak_hz,normal_peak_um,tangential_peak_hz,tangential_peak_um\n";
  std::string line;
  for (const BackbonePoint& b : backbone) {
    line = printf_string("%.10g,%.3f,%.6f,%.3f,%.6f\n", b.amplitude_v, b.normal_peak_hz, b.normal_peak_um,
                         b.tangential_peak_hz, b.tangential_peak_um);
    out += line;
  }
  return out;
}

std::string stator_json(const std::vector<StatorRow>& rows, const std::vector<BackbonePoint>& backbone) {
  nlohmann::ordered_json j;
  j["rows"] = nlohmann::ordered_json::array();
  for (const StatorRow& r : rows) {
    j["rows"].push_back({{"amplitude_v", r.amplitude_v},
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
    j["backbone"].push_back({{"amplitude_v", b.amplitude_v},
                             {"normal_peak_hz", b.normal_peak_hz},
                             {"normal_peak_um", b.normal_peak_um},
                             {"tangential_peak_hz", b.tangential_peak_hz},
                             {"tangential_peak_um", b.tangential_peak_um}});
  }
  return j.dump(2) + "\n";
}

void write_stator_plot(const std::vector<SweepPoint>& sweep, const std::vector<double>& voltages,
                       const std::vector<double>& frequencies, const std::vector<BackbonePoint>& backbone,
                       StatorMode mode, const std::filesystem::path& path) {
  const bool vs_frequency = frequencies.size() > 1;
  const char* axis = mode == StatorMode::l1 ? "normal" : "tangential";
  PlotSpec spec;
  spec.title = std::string("Free stator, tip ") + axis + " amplitude (harmonic balance)";
  spec.x_label = vs_frequency ? "frequency (kHz)" : "amplitude (V)";
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
        s.x.push_back(vs_frequency ? p.response.frequency_hz * 1e-3 : p.response.amplitude_v);
        s.y.push_back(b.tip_amplitude_um);
      }
    }
    if (!s.x.empty()) spec.series.push_back(std::move(s));
  };
  if (vs_frequency) {
    for (double v : voltages) {
      add_series(
          amplitude_v_label(v), [v](const SweepPoint& p) { return p.response.amplitude_v == v; }, true);
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

}  // namespace swum::host
