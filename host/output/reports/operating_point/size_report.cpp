#include "output/reports/operating_point/size_report.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>

#include "formats/number_format.h"
#include "output/plot.h"
#include "output/reports/report_values.h"

namespace swum::host {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kSizeHeader =
    "amplitude_v,load_n,temperature_rise_k,sized,frequency_hz,peak_frequency_hz,speed_mm_s,"
    "current_rms_a_a,current_peak_a_a,phase_a_deg,motional_phase_a_deg,power_a_w,apparent_power_a_va,power_factor_a,"
    "current_rms_b_a,current_peak_b_a,phase_b_deg,motional_phase_b_deg,power_b_w,apparent_power_b_va,power_factor_b,"
    "electrical_power_w,mechanical_power_w,efficiency,stator_heat_w,"
    "parallel_amplifier_current_a_a,parallel_amplifier_phase_a_deg,series_source_voltage_a_v,"
    "series_amplifier_current_a_a,series_amplifier_phase_a_deg,reason\n";

std::string cell(double v) { return std::isfinite(v) ? format_number(v, "%.6g") : ""; }

std::string csv_text(std::string text) {
  std::replace(text.begin(), text.end(), ',', ';');
  return text;
}

double inductor_current_a(double voltage_v, double frequency_hz, double inductance_h) {
  return voltage_v / (2.0 * std::numbers::pi * frequency_hz * inductance_h);
}

// The largest current amplitude through a parallel inductor over the sized rows.
double worst_inductor_current_a(const SizingResult& s, double inductance_h, bool phase_a) {
  double worst = 0.0;
  for (const SizingRow& r : s.rows) {
    if (!r.sized) continue;
    worst = std::max(worst, inductor_current_a(phase_a ? r.a.voltage_v : r.b.voltage_v, r.frequency_hz, inductance_h));
  }
  return worst;
}

std::string where(const SizingResult& s, const Extreme& e) {
  if (!e.known) return "-";
  const SizingRow& r = s.rows[e.row];
  std::string t = format_number(r.amplitude_v) + " V, " + format_number(r.load_n) + " N, " +
                  format_number(r.temperature_rise_k) + " K, " + format_number(r.frequency_hz, "%.10g") + " Hz";
  if (e.phase != ' ') t += ", phase " + std::string(1, static_cast<char>(e.phase - 'a' + 'A'));
  return t;
}

// The worst cases over the envelope, once for the JSON's "worst", the text's lines and the report's
// table, in their order: the JSON key, the text's name (none: the text leaves the figure out), the
// report's name, the figure, its unit and number format; the text's unit where it differs (plain
// "deg", "amplitude" spelled out). The matching network's figures come last: the text gives them
// after the network, only when one was designed.
struct WorstCase {
  const char* key;
  const char* text_name;
  const char* report_name;
  Extreme SizingSummary::*extreme;
  const char* unit;
  const char* format;
  const char* text_unit = nullptr;  // none: unit
  bool network = false;
};
constexpr WorstCase kWorstCases[] = {
    {"current_rms_a", "worst RMS current per phase", "RMS current per phase", &SizingSummary::current_rms_a, " A",
     "%.4g"},
    {"current_peak_a", "worst peak current per phase", "peak current per phase", &SizingSummary::current_peak_a, " A",
     "%.4g"},
    {"apparent_power_va", "worst apparent power per phase", "apparent power per phase",
     &SizingSummary::apparent_power_va, " VA", "%.4g"},
    {"power_w", "worst real power per phase", "real power per phase", &SizingSummary::power_w, " W", "%.4g"},
    {"power_factor_min", "lowest power factor", "power factor (lowest)", &SizingSummary::power_factor_min, "", "%.3f"},
    {"electrical_power_w", nullptr, "electrical power, both phases", &SizingSummary::electrical_power_w, " W", "%.4g"},
    {"mechanical_power_w", "most mechanical output", "mechanical output", &SizingSummary::mechanical_power_w, " W",
     "%.4g"},
    {"efficiency_min", "lowest efficiency (loaded rows)", "efficiency (lowest, loaded rows)",
     &SizingSummary::efficiency_min, "", "%.3f"},
    {"stator_heat_w", "most heat into the stator", "heat into the stator", &SizingSummary::stator_heat_w, " W", "%.4g"},
    {"parallel_amplifier_current_a", "worst amplifier current with the parallel inductor",
     "amplifier current with the parallel inductor", &SizingSummary::parallel_current_amplitude_a, " A", "%.4g",
     " A (amplitude)", true},
    {"parallel_amplifier_phase_abs_deg", "worst amplifier phase with the parallel inductor",
     "amplifier current phase with the parallel inductor (abs)", &SizingSummary::parallel_phase_abs_deg, " °", "%.3g",
     " deg", true},
    {"series_source_voltage_v", "worst amplifier voltage with the series inductor",
     "amplifier voltage with the series inductor", &SizingSummary::series_source_voltage_v, " V", "%.4g",
     " V (amplitude)", true},
    {"series_amplifier_current_a", nullptr, "amplifier current with the series inductor",
     &SizingSummary::series_current_amplitude_a, " A", "%.4g", nullptr, true},
};

Json extreme_json(const SizingResult& s, const Extreme& e) {
  if (!e.known) return Json(nullptr);
  const SizingRow& r = s.rows[e.row];
  Json j;
  j["value"] = finite_or_null(e.value);
  j["row"] = e.row;
  j["amplitude_v"] = r.amplitude_v;
  j["load_n"] = r.load_n;
  j["temperature_rise_k"] = r.temperature_rise_k;
  j["frequency_hz"] = r.frequency_hz;
  j["phase"] = e.phase == ' ' ? Json(nullptr) : Json(std::string(1, e.phase));
  return j;
}

Json phase_json(const PhaseDuty& d, const MatchedDuty& m) {
  Json j;
  j["voltage_v"] = d.voltage_v;
  j["current_rms_a"] = d.current_rms_a;
  j["current_peak_a"] = d.current_peak_a;
  j["current_amplitude_a"] = d.current_amplitude_a;
  j["phase_deg"] = d.phase_deg;
  j["motional_phase_deg"] = d.motional_phase_deg;
  j["power_w"] = d.power_w;
  j["apparent_power_va"] = d.apparent_power_va;
  j["power_factor"] = d.power_factor;
  j["conductance_siemens"] = d.admittance_siemens.real();
  j["susceptance_siemens"] = d.admittance_siemens.imag();
  j["parallel_amplifier_current_a"] = finite_or_null(m.parallel_current_amplitude_a);
  j["parallel_amplifier_phase_deg"] = finite_or_null(m.parallel_current_phase_deg);
  j["series_source_voltage_v"] = finite_or_null(m.series_source_voltage_v);
  j["series_amplifier_current_a"] = finite_or_null(m.series_current_amplitude_a);
  j["series_amplifier_phase_deg"] = finite_or_null(m.series_current_phase_deg);
  return j;
}

Json design_json(const MatchingDesign& d, const SizingResult& s, bool phase_a) {
  Json j;
  j["frequency_hz"] = d.angular_frequency_rad_s / (2.0 * std::numbers::pi);
  j["voltage_v"] = d.voltage_v;
  j["conductance_siemens"] = d.admittance_siemens.real();
  j["susceptance_siemens"] = d.admittance_siemens.imag();
  j["c0_parallel_inductance_uh"] = d.c0_parallel_inductance_h * 1e6;
  j["parallel_inductance_uh"] = number_or_null(d.parallel_ok, d.parallel_inductance_h * 1e6);
  j["parallel_amplifier_current_a"] = number_or_null(d.parallel_ok, d.parallel_current_amplitude_a);
  j["parallel_inductor_worst_current_a"] = number_or_null(
      d.parallel_ok, d.parallel_ok ? worst_inductor_current_a(s, d.parallel_inductance_h, phase_a) : 0.0);
  j["series_inductance_uh"] = number_or_null(d.series_ok, d.series_inductance_h * 1e6);
  j["series_source_voltage_v"] = number_or_null(d.series_ok, d.series_source_voltage_v);
  j["series_amplifier_current_a"] = number_or_null(d.series_ok, d.series_current_amplitude_a);
  return j;
}

Json figure_json(const PopulationFigure& f) { return f.reached ? Json(f.value) : Json(nullptr); }

Json population_json(const PopulationSizing& p, const SizeContext& c) {
  Json j;
  j["spreads"] = c.spreads_path;
  j["seed"] = c.seed;
  j["motors"] = p.motors;
  j["sized"] = p.sized;
  j["yield"] = p.yield;
  j["needed"] = p.needed;
  j["oscillator"] = p.oscillator_reached ? Json{{"low_hz", p.oscillator_low_hz},
                                                {"high_hz", p.oscillator_high_hz},
                                                {"width_hz", p.oscillator_high_hz - p.oscillator_low_hz},
                                                {"covered", p.oscillator_covered}}
                                         : Json(nullptr);
  j["current_rms_a"] = figure_json(p.current_rms_a);
  j["current_peak_a"] = figure_json(p.current_peak_a);
  j["apparent_power_va"] = figure_json(p.apparent_power_va);
  j["power_w"] = figure_json(p.power_w);
  j["stator_heat_w"] = figure_json(p.stator_heat_w);
  j["parallel_amplifier_current_a"] = figure_json(p.parallel_current_amplitude_a);
  j["parallel_amplifier_phase_abs_deg"] = figure_json(p.parallel_phase_abs_deg);
  j["series_source_voltage_v"] = figure_json(p.series_source_voltage_v);
  return j;
}

// "x.xx UNIT" or "not reached".
std::string figure_text(const PopulationFigure& f, const char* unit, const char* fmt = "%.4g") {
  return f.reached ? format_number(f.value, fmt) + unit : std::string("not reached");
}

std::string population_lines(const PopulationSizing& p, const char* bullet, const char* sub) {
  std::string t;
  const std::string share = format_number(100.0 * p.yield, "%.3g") + " %";
  t += std::string(bullet) + "population: " + format_number(static_cast<double>(p.motors)) + " motors, " +
       format_number(static_cast<double>(p.sized)) + " sized at every row; for " + share + " (" +
       format_number(static_cast<double>(p.needed)) + " motors):\n";
  t += std::string(sub) + "oscillator " +
       (p.oscillator_reached
            ? format_number(p.oscillator_low_hz, "%.10g") + " .. " + format_number(p.oscillator_high_hz, "%.10g") +
                  " Hz (covers " + format_number(static_cast<double>(p.oscillator_covered)) + ")"
            : std::string("not reached")) +
       "\n";
  t += std::string(sub) + "RMS current per phase up to " + figure_text(p.current_rms_a, " A") + ", peak " +
       figure_text(p.current_peak_a, " A") + ", apparent power " + figure_text(p.apparent_power_va, " VA") +
       ", real power " + figure_text(p.power_w, " W") + " per phase, stator heat " +
       figure_text(p.stator_heat_w, " W") + "\n";
  t += std::string(sub) + "with the nominal motor's parallel inductors: amplifier current up to " +
       figure_text(p.parallel_current_amplitude_a, " A") + " amplitude, within " +
       figure_text(p.parallel_phase_abs_deg, "°", "%.3g") +
       " of the voltage; with its series inductors: " + figure_text(p.series_source_voltage_v, " V") +
       " amplitude from the amplifier\n";
  return t;
}

Json series_in_loop_json(const SeriesInLoop& l) {
  Json j;
  j["converged"] = l.converged;
  j["reason"] = l.reason;
  j["rounds"] = l.rounds;
  j["source_resistance_ohm"] = l.source_resistance_ohm;
  j["series_inductance_uh"] = l.inductance_h * 1e6;
  j["source_voltage_v"] = l.source_voltage_v;
  j["terminal_a_v"] = l.terminal_a_v;
  j["terminal_b_v"] = l.terminal_b_v;
  j["amplifier_current_a"] = l.current_a_a;
  j["amplifier_current_phase_deg"] = l.current_phase_a_deg;
  return j;
}

std::string series_in_loop_text(const SeriesInLoop& l) {
  std::string t = "series inductor sized in the loop (R_s " + format_number(l.source_resistance_ohm, "%.3g") +
                  " ohm, phase A): ";
  if (!l.converged) return t + "not found: " + l.reason;
  return t + format_number(l.inductance_h * 1e6, "%.4g") + " µH from " + format_number(l.source_voltage_v, "%.4g") +
         " V amplitude; phase A reaches " + format_number(l.terminal_a_v, "%.4g") + " V, phase B " +
         format_number(l.terminal_b_v, "%.4g") + " V (the same inductor), the amplifier's current " +
         format_number(l.current_a_a, "%.3g") + " A at " + format_number(l.current_phase_a_deg, "%.3g") + "° (" +
         std::to_string(l.rounds) + " rounds)";
}

std::string uh(double h) { return format_number(h * 1e6, "%.4g") + " µH"; }
std::string amps(double a) { return format_number(a, "%.3g") + " A"; }

}  // namespace

std::string size_csv(const SizingResult& s) {
  std::string csv = kSizeHeader;
  for (const SizingRow& r : s.rows) {
    csv += format_number(r.amplitude_v) + "," + format_number(r.load_n) + "," + format_number(r.temperature_rise_k) +
           "," + (r.sized ? "1" : "0") + ",";
    if (r.sized) {
      csv += format_number(r.frequency_hz, "%.10g") + "," + format_number(r.pick.peak_frequency_hz, "%.10g") + "," +
             cell(r.speed_mm_s);
      for (const PhaseDuty* d : {&r.a, &r.b}) {
        csv += "," + cell(d->current_rms_a) + "," + cell(d->current_peak_a) + "," + cell(d->phase_deg) + "," +
               cell(d->motional_phase_deg) + "," + cell(d->power_w) + "," + cell(d->apparent_power_va) + "," +
               cell(d->power_factor);
      }
      csv += "," + cell(r.electrical_power_w) + "," + cell(r.mechanical_power_w) + "," + cell(r.efficiency) + "," +
             cell(r.stator_heat_w) + "," + cell(r.matched_a.parallel_current_amplitude_a) + "," +
             cell(r.matched_a.parallel_current_phase_deg) + "," + cell(r.matched_a.series_source_voltage_v) + "," +
             cell(r.matched_a.series_current_amplitude_a) + "," + cell(r.matched_a.series_current_phase_deg);
    } else {
      csv += std::string(25, ',');  // the 26 number cells between `sized` and `reason`
    }
    csv += "," + csv_text(r.reason) + "\n";
  }
  return csv;
}

std::string size_json(const SizingResult& s, const SizeContext& context) {
  Json rows = Json::array();
  for (const SizingRow& r : s.rows) {
    Json j;
    j["amplitude_v"] = r.amplitude_v;
    j["load_n"] = r.load_n;
    j["temperature_rise_k"] = r.temperature_rise_k;
    j["sized"] = r.sized;
    j["frequency_hz"] = number_or_null(r.sized, r.frequency_hz);
    j["peak_frequency_hz"] = number_or_null(r.pick.decided, r.pick.peak_frequency_hz);
    j["speed_mm_s"] = number_or_null(r.sized, r.speed_mm_s);
    j["phase_a"] = r.sized ? phase_json(r.a, r.matched_a) : Json(nullptr);
    j["phase_b"] = r.sized ? phase_json(r.b, r.matched_b) : Json(nullptr);
    j["electrical_power_w"] = number_or_null(r.sized, r.electrical_power_w);
    j["mechanical_power_w"] = number_or_null(r.sized, r.mechanical_power_w);
    j["efficiency"] = number_or_null(r.sized, r.efficiency);
    j["stator_heat_w"] = number_or_null(r.sized, r.stator_heat_w);
    j["reason"] = r.reason;
    rows.push_back(j);
  }
  const SizingSummary& m = s.summary;
  Json worst;
  for (const WorstCase& w : kWorstCases) worst[w.key] = extreme_json(s, m.*w.extreme);
  Json j;
  j["config"] = context.config_path;
  j["min_margin_hz"] = context.margin_hz;
  j["clamped_capacitance_nf"] = context.clamped_capacitance_f * 1e9;
  j["rows_sized"] = m.sized;
  j["rows"] = s.rows.size();
  j["oscillator"] = m.band.band ? Json{{"low_hz", m.band.band->low_hz},
                                       {"high_hz", m.band.band->high_hz},
                                       {"width_hz", m.band.band->high_hz - m.band.band->low_hz}}
                                : Json(nullptr);
  j["worst"] = worst;
  if (s.designed) {
    const SizingRow& d = s.rows[s.design_row];
    j["network"] = Json{{"design_row", s.design_row},
                        {"amplitude_v", d.amplitude_v},
                        {"load_n", d.load_n},
                        {"temperature_rise_k", d.temperature_rise_k},
                        {"phase_a", design_json(s.design_a, s, true)},
                        {"phase_b", design_json(s.design_b, s, false)}};
  } else {
    j["network"] = nullptr;
  }
  j["population"] = context.population ? population_json(*context.population, context) : Json(nullptr);
  j["series_in_loop"] = context.series_in_loop ? series_in_loop_json(*context.series_in_loop) : Json(nullptr);
  j["table"] = rows;
  return j.dump(2) + "\n";
}

std::string size_text(const SizingResult& s, const SizeContext& context, const std::string& out_path) {
  const SizingSummary& m = s.summary;
  std::string t = format_number(static_cast<double>(m.sized)) + " of " +
                  format_number(static_cast<double>(s.rows.size())) + " rows sized";
  if (m.band.band) {
    t += "; oscillator " + format_number(m.band.band->low_hz, "%.10g") + " .. " +
         format_number(m.band.band->high_hz, "%.10g") + " Hz";
  }
  t += "\n";
  // The worst cases of one group (kWorstCases): the motor's, or the matching network's.
  auto lines = [&](bool network) {
    for (const WorstCase& w : kWorstCases) {
      const Extreme& e = m.*w.extreme;
      if (w.network != network || w.text_name == nullptr || !e.known) continue;
      t += std::string("  ") + w.text_name + ": " + format_number(e.value, w.format) +
           (w.text_unit != nullptr ? w.text_unit : w.unit) + "  (" + where(s, e) + ")\n";
    }
  };
  lines(false);
  if (s.designed) {
    const SizingRow& d = s.rows[s.design_row];
    t += "network sized at " + format_number(d.amplitude_v) + " V, " + format_number(d.load_n) + " N, " +
         format_number(d.temperature_rise_k) + " K, " + format_number(d.frequency_hz, "%.10g") + " Hz:\n";
    for (const auto& [name, design] : {std::pair{"A", &s.design_a}, std::pair{"B", &s.design_b}}) {
      t += std::string("  phase ") + name + ": C0 alone " + uh(design->c0_parallel_inductance_h);
      if (design->parallel_ok) t += ", parallel " + uh(design->parallel_inductance_h);
      if (design->series_ok) {
        t += ", or series " + uh(design->series_inductance_h) + " from " +
             format_number(design->series_source_voltage_v, "%.4g") + " V";
      }
      t += "\n";
    }
    lines(true);
  } else if (s.design_row < s.rows.size()) {
    t += "no network: the design row was not sized (" + s.rows[s.design_row].reason + ")\n";
  }
  for (const SizingRow& r : s.rows) {
    if (!r.sized) {
      t += "  not sized: " + format_number(r.amplitude_v) + " V, " + format_number(r.load_n) + " N, " +
           format_number(r.temperature_rise_k) + " K: " + r.reason + "\n";
    }
  }
  if (context.series_in_loop) t += "  " + series_in_loop_text(*context.series_in_loop) + "\n";
  if (context.population) t += population_lines(*context.population, "", "  ");
  if (!out_path.empty()) t += "rows: " + out_path + "\n";
  return t;
}

std::string size_markdown(const SizingResult& s, const SizeContext& context, const std::vector<std::string>& plots) {
  const SizingSummary& m = s.summary;
  std::string t = "# Amplifier sizing\n\n";
  t += "Made by `" + context.command + "`";
  if (!context.config_path.empty()) t += " from `" + context.config_path + "`";
  t += ". Every figure is the model's steady state at the drift-aware operating point of its row (the "
       "frequency `swum band` picks: " +
       format_number(context.margin_hz) +
       " Hz or more above the softening peak of a continuous down-sweep), interpolated between the two grid "
       "points either side. Voltages and currents are amplitudes (zero-to-peak) unless named RMS; the "
       "phase of a current is against its voltage, + = leading. C0 = " +
       format_number(context.clamped_capacitance_f * 1e9, "%.4g") + " nF per phase.\n\n";
  t += "## What to buy\n\n";
  if (m.band.band) {
    t += "- **Oscillator**: " + format_number(m.band.band->low_hz, "%.10g") + " .. " +
         format_number(m.band.band->high_hz, "%.10g") + " Hz (" +
         format_number(m.band.band->high_hz - m.band.band->low_hz, "%.10g") + " Hz wide).\n";
  }
  if (s.designed) {
    const SizingRow& d = s.rows[s.design_row];
    t += "- **Matching network**, sized at the design row " + format_number(d.amplitude_v) + " V, " +
         format_number(d.load_n) + " N, " + format_number(d.temperature_rise_k) + " K, " +
         format_number(d.frequency_hz, "%.10g") + " Hz (the highest voltage, unloaded, coldest):\n";
    for (const auto& [name, design, phase_a] :
         {std::tuple{"A", &s.design_a, true}, std::tuple{"B", &s.design_b, false}}) {
      if (design->parallel_ok) {
        const double il = worst_inductor_current_a(s, design->parallel_inductance_h, phase_a);
        t += std::string("  - phase ") + name + ": a **parallel inductor of " + uh(design->parallel_inductance_h) +
             "** rated for " + amps(il) + " amplitude (" + amps(il / std::numbers::sqrt2) +
             " RMS); it cancels the phase's whole susceptance at the design row (" +
             uh(design->c0_parallel_inductance_h) + " would cancel C0 alone)";
      }
      if (design->series_ok) {
        t += std::string(design->parallel_ok ? "; or" : std::string("  - phase ") + name + ":") +
             " a **series inductor of " + uh(design->series_inductance_h) + "** from " +
             format_number(design->series_source_voltage_v, "%.4g") + " V amplitude";
      }
      t += ".\n";
    }
    if (m.parallel_current_amplitude_a.known) {
      t += "- **Amplifier with the parallel inductors**: the phase voltage itself (" + format_number(d.amplitude_v) +
           " V amplitude at the design row); output current up to " + amps(m.parallel_current_amplitude_a.value) +
           " amplitude (" + amps(m.parallel_current_amplitude_a.value / std::numbers::sqrt2) + " RMS) per phase (" +
           where(s, m.parallel_current_amplitude_a) + "), within " +
           format_number(m.parallel_phase_abs_deg.value, "%.3g") + "° of its voltage over the envelope.\n";
    }
    if (m.series_source_voltage_v.known) {
      t += "- **Amplifier with the series inductors instead**: up to " +
           format_number(m.series_source_voltage_v.value, "%.4g") + " V amplitude (" +
           where(s, m.series_source_voltage_v) + ") and " + amps(m.series_current_amplitude_a.value) +
           " amplitude. **A first estimate only**: these come from the motor driven by an ideal source; the "
           "inductor and C0 form a resonant step-up (gain ~6) that moves the motor's state";
      // With the design repeated in the loop (the next bullet), that figure is the one to build.
      if (context.series_in_loop && context.series_in_loop->converged) {
        t += " (docs/amplifier.md: one-shot figures for 200 V gave 332 V there), so build a series-matched board "
             "to the figures sized in the loop below, not to these";
      } else {
        t += ", so a series-matched board must be sized again on the state it makes, in the loop with "
             "`[amplifier]` (docs/amplifier.md: one-shot figures for 200 V gave 332 V there)";
      }
      t += ". Prefer the parallel inductors.\n";
    }
  }
  if (context.series_in_loop) {
    t += "- **The series inductor sized in the loop** (the design repeated in the simulator with the network as "
         "`[amplifier]` until phase A holds its voltage): " +
         series_in_loop_text(*context.series_in_loop) + ".\n";
  }
  if (m.current_rms_a.known) {
    t += "- **Without a network** the amplifier delivers up to " + amps(m.current_rms_a.value) + " RMS (" +
         amps(m.current_peak_a.value) + " peak) and " + format_number(m.apparent_power_va.value, "%.4g") +
         " VA per phase at a power factor down to " + format_number(m.power_factor_min.value, "%.3f") + ".\n";
  }
  if (context.population) {
    t += "\n## A population of motors\n\nMotors drawn from `" + context.spreads_path + "` (seed " +
         format_number(static_cast<double>(context.seed)) +
         ", as `swum population` draws them), each over the same envelope, the network the nominal motor's; every "
         "figure the smallest value that the stated share of the motors' worst cases stays within (a motor not sized "
         "at some row never counts as within).\n\n";
    t += population_lines(*context.population, "- ", "  - ");
  }
  t += "\n## Worst cases over the envelope\n\n| figure | worst | where |\n|---|---|---|\n";
  for (const WorstCase& w : kWorstCases) {
    const Extreme& e = m.*w.extreme;
    if (e.known)
      t += std::string("| ") + w.report_name + " | " + format_number(e.value, w.format) + w.unit + " | " + where(s, e) +
           " |\n";
  }
  t += "\n## Every row\n\n| V | load (N) | rise (K) | f (Hz) | speed (mm/s) | I_rms A/B (A) | phase A/B (°) | P (W) | "
       "S A (VA) | PF A | P_mech (W) | η | heat (W) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const SizingRow& r : s.rows) {
    t += "| " + format_number(r.amplitude_v) + " | " + format_number(r.load_n) + " | " +
         format_number(r.temperature_rise_k) + " | ";
    if (!r.sized) {
      t += "not sized: " + r.reason + " ||||||||||\n";
      continue;
    }
    t += format_number(r.frequency_hz, "%.10g") + " | " + format_number(r.speed_mm_s, "%.4g") + " | " +
         format_number(r.a.current_rms_a, "%.3g") + " / " + format_number(r.b.current_rms_a, "%.3g") + " | " +
         format_number(r.a.phase_deg, "%.3g") + " / " + format_number(r.b.phase_deg, "%.3g") + " | " +
         format_number(r.electrical_power_w, "%.3g") + " | " + format_number(r.a.apparent_power_va, "%.3g") + " | " +
         format_number(r.a.power_factor, "%.3f") + " | " + format_number(r.mechanical_power_w, "%.3g") + " | " +
         format_number(r.efficiency, "%.3f") + " | " + format_number(r.stator_heat_w, "%.3g") + " |\n";
  }
  if (!plots.empty()) {
    t += "\n## Plots\n\n";
    for (const std::string& p : plots) t += "![" + p + "](" + p + ")\n\n";
  }
  t += "## Limits\n\nThe figures are the model's: an ideal sinusoidal source at each row's voltage, the network's "
       "effect on the phase voltage computed from each row's admittance (a quasi-static phasor; docs/sizing.md). "
       "Check the design in the loop with the `[amplifier]` section of the motor file (swum-emu).\n";
  return t;
}

std::vector<std::string> write_size_plots(const std::filesystem::path& dir, const std::vector<BandRow>& rows,
                                          const SizingResult& s) {
  std::vector<std::string> written;
  if (rows.empty() || s.design_row >= rows.size()) return written;
  const BandRow& design = rows[s.design_row];
  // Curves of the design row's load and temperature rise, one per voltage.
  PlotSpec current{"RMS current of phase A along the down-sweep (load " + format_number(design.load_n) + " N, rise " +
                       format_number(design.temperature_rise_k) + " K)",
                   "frequency (kHz)",
                   "current (A RMS)",
                   {}};
  PlotSpec power{"Real power of both phases along the down-sweep", "frequency (kHz)", "power (W)", {}};
  for (const BandRow& r : rows) {
    if (r.load_n != design.load_n || r.temperature_rise_k != design.temperature_rise_k) continue;
    PlotSeries i{format_number(r.amplitude_v) + " V", {}, {}, true, false};
    PlotSeries p = i;
    for (std::size_t k = 0; k < r.curve.size() && k < r.points.size(); ++k) {
      const ElectricalReadings& e = r.points[k].electrical;
      if (!r.curve[k].ok || !e.valid) continue;
      i.x.push_back(r.curve[k].frequency_hz * 1e-3);
      i.y.push_back(e.rms_current_a_a);
      p.x.push_back(r.curve[k].frequency_hz * 1e-3);
      p.y.push_back(e.power_a_w + e.power_b_w);
    }
    current.series.push_back(i);
    power.series.push_back(p);
  }
  PlotSpec magnitude{"Admittance of phase A at the design row (" + format_number(design.amplitude_v) + " V)",
                     "frequency (kHz)",
                     "|Y| (mS)",
                     {}};
  PlotSpec phase{"Phase of the admittance of phase A at the design row", "frequency (kHz)", "phase (deg)", {}};
  PlotSeries ym{"|Y|", {}, {}, true, false};
  PlotSeries yp{"phase", {}, {}, true, false};
  for (std::size_t k = 0; k < design.curve.size() && k < design.points.size(); ++k) {
    const ElectricalReadings& e = design.points[k].electrical;
    if (!design.curve[k].ok || !e.valid || !(e.voltage_a_v > 0.0)) continue;
    ym.x.push_back(design.curve[k].frequency_hz * 1e-3);
    ym.y.push_back(1e3 * e.current_a_a / e.voltage_a_v);
    yp.x.push_back(design.curve[k].frequency_hz * 1e-3);
    yp.y.push_back(e.phase_a_deg);
  }
  magnitude.series.push_back(ym);
  phase.series.push_back(yp);
  // The envelope: per (load, rise) the operating frequency and the worst RMS current against voltage.
  PlotSpec frequency{"Operating frequency over the envelope", "amplitude (V)", "frequency (kHz)", {}};
  PlotSpec worst{
      "RMS current per phase (the larger of A and B) over the envelope", "amplitude (V)", "current (A RMS)", {}};
  std::map<std::pair<double, double>, std::pair<PlotSeries, PlotSeries>> by_corner;
  for (const SizingRow& r : s.rows) {
    if (!r.sized) continue;
    auto& [f, c] = by_corner[{r.load_n, r.temperature_rise_k}];
    f.label = c.label = format_number(r.load_n) + " N, " + format_number(r.temperature_rise_k) + " K";
    f.x.push_back(r.amplitude_v);
    f.y.push_back(r.frequency_hz * 1e-3);
    c.x.push_back(r.amplitude_v);
    c.y.push_back(std::max(r.a.current_rms_a, r.b.current_rms_a));
  }
  for (auto& [corner, series] : by_corner) {
    frequency.series.push_back(series.first);
    worst.series.push_back(series.second);
  }
  auto write = [&](const PlotSpec& spec, const char* name) {
    bool any = false;
    for (const PlotSeries& p : spec.series) any = any || !p.x.empty();
    if (!any) return;
    write_png_plot(spec, dir / name);
    written.emplace_back(name);
  };
  write(magnitude, "admittance_magnitude.png");
  write(phase, "admittance_phase.png");
  write(current, "current_vs_frequency.png");
  write(power, "power_vs_frequency.png");
  write(frequency, "envelope_frequency.png");
  write(worst, "envelope_current.png");
  return written;
}

}  // namespace swum::host
