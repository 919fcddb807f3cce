#include "output/reports/model/admittance_report.h"

#include <algorithm>
#include <array>
#include <nlohmann/json.hpp>
#include <string>

#include "formats/number_format.h"
#include "output/plot.h"
#include "output/reports/report_values.h"

namespace swum::host {

namespace {

constexpr std::array<const char*, kCircuitModes> kModeNames = {"L1", "B2"};

nlohmann::ordered_json circuit_json(const EquivalentCircuit& c) {
  nlohmann::ordered_json j;
  j["clamped_capacitance_nf"] = finite_or_null(c.clamped_capacitance_f * 1e9);
  for (std::size_t i = 0; i < kCircuitModes; ++i) {
    const MotionalBranch& b = c.branches[i];
    j[kModeNames[i]] = {{"motional_resistance_ohm", finite_or_null(b.resistance_ohm)},
                        {"motional_inductance_h", finite_or_null(b.inductance_h)},
                        {"motional_capacitance_pf", finite_or_null(b.capacitance_f * 1e12)}};
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

std::size_t diverged_points(const AdmittanceLevel& l) {
  return static_cast<std::size_t>(
      std::count_if(l.points.begin(), l.points.end(), [](const AdmittancePoint& p) { return p.diverged; }));
}

std::string row(const char* name, double analytic, double fitted, double error, const char* format) {
  return std::string("  ") + name + "  " + format_number(analytic, format) + "  " + format_number(fitted, format) +
         " +- " + format_number(error, "%.2g") + "\n";
}

}  // namespace

std::string admittance_csv(const AdmittanceReport& r) {
  std::string out =
      "amplitude_v,frequency_hz,magnitude_siemens,phase_deg,conductance_siemens,susceptance_siemens,current_a,"
      "diverged\n";
  for (const AdmittanceLevel& l : r.levels) {
    for (const AdmittancePoint& p : l.points) {
      out += format_number(p.amplitude_v, "%.10g") + "," + format_number(p.frequency_hz, "%.10g") + "," +
             format_number(p.magnitude_siemens, "%.8g") + "," + format_number(p.phase_deg, "%.6f") + "," +
             format_number(p.conductance_siemens, "%.8g") + "," + format_number(p.susceptance_siemens, "%.8g") + "," +
             format_number(p.current_a, "%.8g") + "," + (p.diverged ? "1" : "0") + "\n";
    }
  }
  return out;
}

std::string admittance_text(const AdmittanceReport& r) {
  std::string out = "Admittance of phase " + std::string(driven_phase_name(r.phase)) + ", " +
                    std::string(mounting_name(r.mounting)) + " (" + r.source + ")\n";
  out += "BVD circuit: analytic (modal constants)  fitted +- standard error\n";
  for (const AdmittanceLevel& l : r.levels) {
    out += "amplitude " + amplitude_v_label(l.amplitude_v) + ": ";
    if (const std::size_t n = diverged_points(l); n > 0) out += std::to_string(n) + " points diverged; ";
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
      out += row("R_m (ohm)  ", ab.resistance_ohm, fb.resistance_ohm, eb.resistance_ohm, "%.6g");
      out += row("L_m (H)    ", ab.inductance_h, fb.inductance_h, eb.inductance_h, "%.6g");
      out += row("C_m (pF)   ", ab.capacitance_f * 1e12, fb.capacitance_f * 1e12, eb.capacitance_f * 1e12, "%.6g");
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
                        {"magnitude_siemens", finite_or_null(p.magnitude_siemens)},
                        {"phase_deg", finite_or_null(p.phase_deg)},
                        {"conductance_siemens", finite_or_null(p.conductance_siemens)},
                        {"susceptance_siemens", finite_or_null(p.susceptance_siemens)},
                        {"current_a", finite_or_null(p.current_a)},
                        {"diverged", p.diverged}});
    }
    lj["points"] = points;
    levels.push_back(lj);
  }
  j["levels"] = levels;
  return j.dump(2) + "\n";
}

std::string admittance_problem(const AdmittanceReport& r) {
  for (const AdmittanceLevel& l : r.levels) {
    const std::string at = "admittance at " + amplitude_v_label(l.amplitude_v) + ": ";
    if (const std::size_t n = diverged_points(l); n > 0)
      return at + std::to_string(n) + " of " + std::to_string(l.points.size()) +
             " points diverged (the simulator's runaway guard; diverged = 1 in the output, left out of the fit "
             "and the plots)";
    if (!l.fit.ok) return at + "the circuit fit failed: " + l.fit.failure;
  }
  return {};
}

void write_admittance_plots(const AdmittanceReport& r, const std::filesystem::path& dir) {
  const std::string title_tail = " of phase " + std::string(driven_phase_name(r.phase)) + ", " +
                                 std::string(mounting_name(r.mounting));
  PlotSpec magnitude{"Admittance magnitude" + title_tail, "frequency (kHz)", "|Y| (mS)", {}};
  PlotSpec phase{"Admittance phase" + title_tail, "frequency (kHz)", "phase of Y (deg)", {}};
  PlotSpec circle{"Admittance circle" + title_tail, "conductance G (mS)", "susceptance B (mS)", {}};
  for (const AdmittanceLevel& l : r.levels) {
    PlotSeries m{amplitude_v_label(l.amplitude_v), {}, {}};
    PlotSeries p{amplitude_v_label(l.amplitude_v), {}, {}};
    PlotSeries c{amplitude_v_label(l.amplitude_v), {}, {}};
    for (const AdmittancePoint& q : l.points) {
      if (q.diverged) continue;
      m.x.push_back(q.frequency_hz * 1e-3);
      m.y.push_back(q.magnitude_siemens * 1e3);
      p.x.push_back(q.frequency_hz * 1e-3);
      p.y.push_back(q.phase_deg);
      c.x.push_back(q.conductance_siemens * 1e3);
      c.y.push_back(q.susceptance_siemens * 1e3);
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
