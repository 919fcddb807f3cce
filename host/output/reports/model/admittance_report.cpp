#include "output/reports/model/admittance_report.h"

#include <array>
#include <nlohmann/json.hpp>

#include "formats/number_format.h"
#include "output/plot.h"
#include "output/reports/report_values.h"

namespace swum::host {

namespace {

constexpr std::array<const char*, kCircuitModes> kModeNames = {"L1", "B2"};

std::string level_label(double amplitude_v) { return format_number(amplitude_v, "%g") + " V"; }

nlohmann::ordered_json circuit_json(const EquivalentCircuit& c) {
  nlohmann::ordered_json j;
  j["clamped_capacitance_nf"] = finite_or_null(c.clamped_capacitance_f * 1e9);
  for (std::size_t i = 0; i < kCircuitModes; ++i) {
    const MotionalBranch& b = c.branches[i];
    j[kModeNames[i]] = {{"resistance_ohm", finite_or_null(b.resistance_ohm)},
                        {"inductance_h", finite_or_null(b.inductance_h)},
                        {"capacitance_pf", finite_or_null(b.capacitance_f * 1e12)}};
  }
  return j;
}

// Resonances, coupling and Q of each branch (not for a standard-error circuit).
nlohmann::ordered_json derived_json(const EquivalentCircuit& c) {
  nlohmann::ordered_json j;
  for (std::size_t i = 0; i < kCircuitModes; ++i) {
    const MotionalBranch& b = c.branches[i];
    j[kModeNames[i]] = {{"series_resonance_hz", finite_or_null(series_resonance_hz(b))},
                        {"parallel_resonance_hz", finite_or_null(parallel_resonance_hz(b, c.clamped_capacitance_f))},
                        {"coupling_factor_squared",
                         finite_or_null(coupling_factor_squared(b, c.clamped_capacitance_f))},
                        {"quality_factor", finite_or_null(quality_factor(b))}};
  }
  return j;
}

std::string row(const char* name, double analytic, double fitted, double error, const char* format) {
  return std::string("  ") + name + "  " + format_number(analytic, format) + "  " + format_number(fitted, format) +
         " +- " + format_number(error, "%.2g") + "\n";
}

}  // namespace

std::string admittance_csv(const AdmittanceReport& r) {
  std::string out = "amplitude_v,frequency_hz,magnitude_s,phase_deg,conductance_s,susceptance_s,current_a\n";
  for (const AdmittanceLevel& l : r.levels) {
    for (const AdmittancePoint& p : l.points) {
      out += format_number(p.amplitude_v, "%.10g") + "," + format_number(p.frequency_hz, "%.10g") + "," +
             format_number(p.magnitude_s, "%.8g") + "," + format_number(p.phase_deg, "%.6f") + "," +
             format_number(p.conductance_s, "%.8g") + "," + format_number(p.susceptance_s, "%.8g") + "," +
             format_number(p.current_a, "%.8g") + "\n";
    }
  }
  return out;
}

std::string admittance_text(const AdmittanceReport& r) {
  std::string out = "Admittance of phase " + std::string(driven_phase_name(r.phase)) + ", " +
                    std::string(mounting_name(r.mounting)) + " (" + r.source + ")\n";
  out += "BVD circuit: analytic (modal constants)  fitted +- standard error\n";
  for (const AdmittanceLevel& l : r.levels) {
    out += "amplitude " + level_label(l.amplitude_v) + ": ";
    if (!l.fit.ok) {
      out += "fit failed: " + l.fit.failure + "\n";
      continue;
    }
    out += "rms relative residual " + format_number(l.fit.rms_relative_residual, "%.2g") + "\n";
    const EquivalentCircuit& a = r.analytic;
    const EquivalentCircuit& f = l.fit.circuit;
    const EquivalentCircuit& e = l.fit.standard_error;
    out += row("C0 (nF)    ", a.clamped_capacitance_f * 1e9, f.clamped_capacitance_f * 1e9,
               e.clamped_capacitance_f * 1e9, "%.6g");
    for (std::size_t i = 0; i < kCircuitModes; ++i) {
      const MotionalBranch& ab = a.branches[i];
      const MotionalBranch& fb = f.branches[i];
      const MotionalBranch& eb = e.branches[i];
      out += std::string("  ") + kModeNames[i] + "\n";
      out += row("R1 (ohm)   ", ab.resistance_ohm, fb.resistance_ohm, eb.resistance_ohm, "%.6g");
      out += row("L1 (H)     ", ab.inductance_h, fb.inductance_h, eb.inductance_h, "%.6g");
      out += row("C1 (pF)    ", ab.capacitance_f * 1e12, fb.capacitance_f * 1e12, eb.capacitance_f * 1e12, "%.6g");
      out += "  fs, fp (Hz) " + format_number(series_resonance_hz(ab), "%.1f") + ", " +
             format_number(parallel_resonance_hz(ab, a.clamped_capacitance_f), "%.1f") + "  " +
             format_number(series_resonance_hz(fb), "%.1f") + ", " +
             format_number(parallel_resonance_hz(fb, f.clamped_capacitance_f), "%.1f") + "\n";
      out += "  k_eff^2     " + format_number(coupling_factor_squared(ab, a.clamped_capacitance_f), "%.4g") + "  " +
             format_number(coupling_factor_squared(fb, f.clamped_capacitance_f), "%.4g") + "\n";
    }
  }
  return out;
}

std::string admittance_json(const AdmittanceReport& r) {
  nlohmann::ordered_json j;
  j["source"] = r.source;
  j["phase"] = driven_phase_name(r.phase);
  j["mounting"] = mounting_name(r.mounting);
  j["analytic"] = {{"circuit", circuit_json(r.analytic)}, {"derived", derived_json(r.analytic)}};
  nlohmann::ordered_json levels = nlohmann::ordered_json::array();
  for (const AdmittanceLevel& l : r.levels) {
    nlohmann::ordered_json lj;
    lj["amplitude_v"] = l.amplitude_v;
    lj["fit_ok"] = l.fit.ok;
    if (l.fit.ok) {
      lj["circuit"] = circuit_json(l.fit.circuit);
      lj["standard_error"] = circuit_json(l.fit.standard_error);
      lj["derived"] = derived_json(l.fit.circuit);
      lj["rms_relative_residual"] = l.fit.rms_relative_residual;
    } else {
      lj["failure"] = l.fit.failure;
    }
    nlohmann::ordered_json points = nlohmann::ordered_json::array();
    for (const AdmittancePoint& p : l.points) {
      points.push_back({{"frequency_hz", p.frequency_hz},
                        {"magnitude_s", finite_or_null(p.magnitude_s)},
                        {"phase_deg", finite_or_null(p.phase_deg)},
                        {"conductance_s", finite_or_null(p.conductance_s)},
                        {"susceptance_s", finite_or_null(p.susceptance_s)}});
    }
    lj["points"] = points;
    levels.push_back(lj);
  }
  j["levels"] = levels;
  return j.dump(2) + "\n";
}

void write_admittance_plots(const AdmittanceReport& r, const std::filesystem::path& dir) {
  const std::string title_tail = " of phase " + std::string(driven_phase_name(r.phase)) + ", " +
                                 std::string(mounting_name(r.mounting));
  PlotSpec magnitude{"Admittance magnitude" + title_tail, "frequency (kHz)", "|Y| (mS)", {}};
  PlotSpec phase{"Admittance phase" + title_tail, "frequency (kHz)", "phase of Y (deg)", {}};
  PlotSpec circle{"Admittance circle" + title_tail, "conductance G (mS)", "susceptance B (mS)", {}};
  for (const AdmittanceLevel& l : r.levels) {
    PlotSeries m{level_label(l.amplitude_v), {}, {}};
    PlotSeries p{level_label(l.amplitude_v), {}, {}};
    PlotSeries c{level_label(l.amplitude_v), {}, {}};
    for (const AdmittancePoint& q : l.points) {
      m.x.push_back(q.frequency_hz * 1e-3);
      m.y.push_back(q.magnitude_s * 1e3);
      p.x.push_back(q.frequency_hz * 1e-3);
      p.y.push_back(q.phase_deg);
      c.x.push_back(q.conductance_s * 1e3);
      c.y.push_back(q.susceptance_s * 1e3);
    }
    magnitude.series.push_back(m);
    phase.series.push_back(p);
    circle.series.push_back(c);
  }
  write_png_plot(magnitude, dir / "admittance_magnitude.png");
  write_png_plot(phase, dir / "admittance_phase.png");
  write_png_plot(circle, dir / "admittance_circle.png");
}

}  // namespace swum::host
