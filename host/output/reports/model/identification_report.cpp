#include "output/reports/model/identification_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "analysis/free_stator/harmonic_balance.h"
#include "formats/number_format.h"
#include "output/plot.h"

namespace swum::host {

namespace fs = std::filesystem;

namespace {

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

}  // namespace

std::string identification_json(const IdentificationResult& r) { return to_json(r).dump(2) + "\n"; }

std::string identification_summary_text(const IdentificationResult& r) {
  std::string out = "parameter          value          std. error   status\n";
  for (const ParameterEstimate& e : r.parameters) {
    std::string line;
    if (e.identifiable) {
      line = printf_string("%-18s %-14s %-12s identified%s\n", std::string(e.key).c_str(),
                           format_number(e.value, "%+.5g").c_str(), format_number(e.standard_error, "%.2g").c_str(),
                           e.significant ? ", significantly non-zero" : ", NOT significantly non-zero");
    } else {
      line = printf_string("%-18s %-14s %-12s not identifiable, kept at prior: %s\n", std::string(e.key).c_str(),
                           format_number(e.prior, "%+.5g").c_str(), "-", e.reason.c_str());
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

std::string identification_fitted_header(const std::string& command_line, const IdentificationResult& r) {
  std::string header = "# Written by `swum identify " + command_line +
                       "`.\n# Non-linear constants (paper Sec. 4, docs/model_spec.md §6.5):\n";
  for (const ParameterEstimate& e : r.parameters) {
    header += "#   " + std::string(e.key) + " = " + format_number(e.value, "%.6g");
    header += e.identifiable ? " +- " + format_number(e.standard_error, "%.2g") + " (fitted)"
                             : " (prior kept: not identifiable by these data)";
    header += "\n";
  }
  header += "#   RMS relative residual " + format_number(100.0 * r.rms_relative_residual, "%.3g") + " % over " +
            std::to_string(r.residual_count) + " amplitudes\n\n";
  return header;
}

std::string identification_residuals_csv(const IdentificationResult& r) {
  std::string csv = "amplitude_v,frequency_hz,tip_normal_um,fit_normal_um,tip_tangential_um,fit_tangential_um\n";
  auto cell = [](const std::optional<double>& v) { return v ? format_number(*v, "%.6g") : std::string(); };
  for (const PointPrediction& p : r.predictions) {
    csv += format_number(p.measurement.amplitude_v, "%.10g") + "," +
           format_number(p.measurement.frequency_hz, "%.10g") + "," + cell(p.measurement.tip_normal_um) + "," +
           cell(p.predicted_normal_um) + "," + cell(p.measurement.tip_tangential_um) + "," +
           cell(p.predicted_tangential_um) + "\n";
  }
  return csv;
}

// Per axis, per frequency: the fitted amplitude along a voltage up-sweep (the branch it
// follows) and the measured points.
void write_identification_plots(const fs::path& dir, const MotorModel& fitted_model,
                                const std::vector<AmplitudeMeasurement>& data) {
  std::map<double, std::vector<const AmplitudeMeasurement*>> by_frequency;
  double v_max = 0.0;
  for (const AmplitudeMeasurement& m : data) {
    by_frequency[m.frequency_hz].push_back(&m);
    v_max = std::max(v_max, m.amplitude_v);
  }
  std::vector<double> grid;
  for (int i = 0; i <= 80; ++i) grid.push_back(v_max * i / 80.0);
  const FreeStatorHarmonicBalance hb(fitted_model);
  for (StatorMode mode : {StatorMode::l1, StatorMode::b2}) {
    const bool normal = mode == StatorMode::l1;
    PlotSpec spec;
    spec.title = std::string("Identification: tip ") + (normal ? "normal" : "tangential") + " amplitude, data and fit";
    spec.x_label = "amplitude (V)";
    spec.y_label = std::string("tip ") + (normal ? "normal" : "tangential") + " amplitude (um)";
    for (const auto& [f, points] : by_frequency) {
      PlotSeries measured;
      measured.label = format_number(f * 1e-3, "%.2f") + " kHz data";
      measured.draw_line = false;
      for (const AmplitudeMeasurement* m : points) {
        const auto& a = normal ? m->tip_normal_um : m->tip_tangential_um;
        if (!a) continue;
        measured.x.push_back(m->amplitude_v);
        measured.y.push_back(*a);
      }
      if (measured.x.empty()) continue;
      PlotSeries fit;
      fit.label = format_number(f * 1e-3, "%.2f") + " kHz fit";
      fit.draw_markers = false;
      for (const SweepPoint& p : sweep_voltage(hb, f, grid)) {
        const int k = normal ? p.followed_normal : p.followed_tangential;
        if (k < 0) continue;
        fit.x.push_back(p.response.amplitude_v);
        fit.y.push_back(p.response.mode(mode).branches[k].tip_amplitude_um);
      }
      spec.series.push_back(std::move(measured));
      if (!fit.x.empty()) spec.series.push_back(std::move(fit));
    }
    if (!spec.series.empty()) {
      write_png_plot(spec, dir / (normal ? "fit_normal.png" : "fit_tangential.png"));
    }
  }
}

}  // namespace swum::host
