#include "analysis/sizing/amplifier_sizing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <utility>

#include "analysis/studies/population.h"

namespace swum {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

PhaseDuty phase_duty(double voltage_v, double current_amplitude_a, double phase_deg, double motional_phase_deg,
                     double current_rms_a, double current_peak_a, double power_w, double apparent_power_va,
                     double power_factor) {
  PhaseDuty d;
  d.voltage_v = voltage_v;
  d.current_amplitude_a = current_amplitude_a;
  d.phase_deg = phase_deg;
  d.motional_phase_deg = motional_phase_deg;
  d.current_rms_a = current_rms_a;
  d.current_peak_a = current_peak_a;
  d.power_w = power_w;
  d.apparent_power_va = apparent_power_va;
  d.power_factor = power_factor;
  d.admittance_siemens = voltage_v > 0.0 ? admittance_from_reading(current_amplitude_a, phase_deg, voltage_v)
                                         : std::complex<double>{};
  return d;
}

PhaseDuty duty_a(const ElectricalReadings& e) {
  return phase_duty(e.voltage_a_v, e.current_a_a, e.phase_a_deg, e.motional_phase_a_deg, e.rms_current_a_a,
                    e.peak_current_a_a, e.power_a_w, e.apparent_power_a_va, e.power_factor_a);
}
PhaseDuty duty_b(const ElectricalReadings& e) {
  return phase_duty(e.voltage_b_v, e.current_b_a, e.phase_b_deg, e.motional_phase_b_deg, e.rms_current_b_a,
                    e.peak_current_b_a, e.power_b_w, e.apparent_power_b_va, e.power_factor_b);
}

void consider(Extreme& e, double value, std::size_t row, char phase, bool smallest = false) {
  if (!std::isfinite(value)) return;
  if (!e.known || (smallest ? value < e.value : value > e.value)) e = Extreme{true, value, row, phase};
}

MatchedDuty matched(const PhaseDuty& d, double angular_frequency_rad_s, const MatchingDesign& design) {
  MatchedDuty m;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  m.parallel_current_amplitude_a = m.parallel_current_phase_deg = nan;
  m.series_source_voltage_v = m.series_current_amplitude_a = m.series_current_phase_deg = nan;
  if (design.parallel_ok) {
    const std::complex<double> i = parallel_amplifier_current(d.admittance_siemens, angular_frequency_rad_s,
                                                              d.voltage_v, design.parallel_inductance_h);
    m.parallel_current_amplitude_a = std::abs(i);
    m.parallel_current_phase_deg = std::arg(i) * kRadToDeg;
  }
  if (design.series_ok) {
    const std::complex<double> vs = series_source_voltage(d.admittance_siemens, angular_frequency_rad_s, d.voltage_v,
                                                          design.series_inductance_h);
    const std::complex<double> i = d.voltage_v * d.admittance_siemens;
    m.series_source_voltage_v = std::abs(vs);
    m.series_current_amplitude_a = std::abs(i);
    m.series_current_phase_deg = std::remainder((std::arg(i) - std::arg(vs)) * kRadToDeg, 360.0);
  }
  return m;
}

}  // namespace

MatchingDesign design_matching(std::complex<double> y, double w, double v, double c0) {
  MatchingDesign d;
  d.angular_frequency_rad_s = w;
  d.voltage_v = v;
  d.admittance_siemens = y;
  d.c0_parallel_inductance_h = c0_compensating_inductance_h(w, c0);
  const MatchingDesignPoint point{y, v, w, c0};
  try {
    const ParallelMatching p = parallel_matching(point);
    d.parallel_ok = true;
    d.parallel_inductance_h = p.inductance_h;
    d.parallel_current_amplitude_a = p.amplifier_current_a;
  } catch (const std::invalid_argument& e) {
    d.parallel_reason = e.what();
  }
  try {
    const SeriesMatching m = series_matching(point);
    d.series_ok = true;
    d.series_inductance_h = m.inductance_h;
    d.series_source_voltage_v = m.amplifier_output_v;
    d.series_current_amplitude_a = m.amplifier_current_a;
  } catch (const std::invalid_argument& e) {
    d.series_reason = e.what();
  }
  return d;
}

bool duty_at_pick(const BandRow& row, SizingRow& out) {
  out.amplitude_v = row.amplitude_v;
  out.load_n = row.load_n;
  out.temperature_rise_k = row.temperature_rise_k;
  out.pick = row.pick;
  if (!row.pick.decided) {
    out.reason = "undecided: " + row.pick.reason;
    return false;
  }
  const double f = row.pick.frequency_hz;
  // The port's figures at the pick: band_electrical_at interpolates them between the grid points
  // either side (both above the peak); the stator's heat between the same two points here.
  const std::optional<ElectricalReadings> e = band_electrical_at(row, f);
  const std::optional<BandInterpolation> at = band_interpolation_at(row, f);
  if (!e || !at) {
    out.reason = "the electrical port was not read at the grid points either side of " + std::to_string(f) + " Hz";
    return false;
  }
  out.frequency_hz = f;
  out.speed_mm_s = row.pick.speed_mm_s;
  out.a = duty_a(*e);
  out.b = duty_b(*e);
  out.electrical_power_w = out.a.power_w + out.b.power_w;
  out.mechanical_power_w = row.load_n * out.speed_mm_s * 1e-3;
  out.efficiency = out.electrical_power_w > 0.0 ? out.mechanical_power_w / out.electrical_power_w : 0.0;
  const double t = at->weight;
  out.stator_heat_w = (1.0 - t) * row.points[at->upper].damping_power_w + t * row.points[at->lower].damping_power_w;
  out.sized = true;
  return true;
}

std::size_t default_design_row(const std::vector<BandRow>& rows) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const BandRow& r = rows[i];
    const BandRow& b = rows[best];
    const bool better = r.amplitude_v > b.amplitude_v ||
                        (r.amplitude_v == b.amplitude_v &&
                         (r.load_n < b.load_n ||
                          (r.load_n == b.load_n && r.temperature_rise_k < b.temperature_rise_k)));
    if (better) best = i;
  }
  return best;
}

namespace {

// The figures of every row, the worst cases, and the duty through result's network (designed).
void finish_sizing(SizingResult& result) {
  SizingSummary& s = result.summary;
  for (std::size_t i = 0; i < result.rows.size(); ++i) {
    SizingRow& r = result.rows[i];
    if (!r.sized) continue;
    ++s.sized;
    const double w = 2.0 * std::numbers::pi * r.frequency_hz;
    if (result.designed) {
      r.matched_a = matched(r.a, w, result.design_a);
      r.matched_b = matched(r.b, w, result.design_b);
    }
    for (const auto& [d, m, phase] : {std::tuple{&r.a, &r.matched_a, 'a'}, std::tuple{&r.b, &r.matched_b, 'b'}}) {
      consider(s.current_rms_a, d->current_rms_a, i, phase);
      consider(s.current_peak_a, d->current_peak_a, i, phase);
      consider(s.apparent_power_va, d->apparent_power_va, i, phase);
      consider(s.power_w, d->power_w, i, phase);
      consider(s.power_factor_min, d->power_factor, i, phase, true);
      consider(s.parallel_current_amplitude_a, m->parallel_current_amplitude_a, i, phase);
      consider(s.parallel_phase_abs_deg, std::abs(m->parallel_current_phase_deg), i, phase);
      consider(s.series_source_voltage_v, m->series_source_voltage_v, i, phase);
      consider(s.series_current_amplitude_a, m->series_current_amplitude_a, i, phase);
    }
    consider(s.electrical_power_w, r.electrical_power_w, i, ' ');
    consider(s.mechanical_power_w, r.mechanical_power_w, i, ' ');
    if (r.load_n > 0.0) consider(s.efficiency_min, r.efficiency, i, ' ', true);
    consider(s.stator_heat_w, r.stator_heat_w, i, ' ');
  }
}

}  // namespace

SizingResult size_amplifier(const std::vector<BandRow>& rows, double clamped_capacitance_f, std::size_t design_row) {
  SizingResult result;
  result.summary.band = summarize_band(rows);
  result.rows.resize(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i)
    (void)duty_at_pick(rows[i], result.rows[i]);  // a row says why in its reason
  result.design_row = design_row;
  if (design_row < result.rows.size() && result.rows[design_row].sized) {
    const SizingRow& d = result.rows[design_row];
    const double w = 2.0 * std::numbers::pi * d.frequency_hz;
    result.design_a = design_matching(d.a.admittance_siemens, w, d.a.voltage_v, clamped_capacitance_f);
    result.design_b = design_matching(d.b.admittance_siemens, w, d.b.voltage_v, clamped_capacitance_f);
    result.designed = true;
  }
  finish_sizing(result);
  return result;
}

SizingResult size_amplifier_with_network(const std::vector<BandRow>& rows, const MatchingDesign& design_a,
                                         const MatchingDesign& design_b) {
  SizingResult result;
  result.summary.band = summarize_band(rows);
  result.rows.resize(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) (void)duty_at_pick(rows[i], result.rows[i]);
  result.design_row = rows.size();  // none of these rows
  result.design_a = design_a;
  result.design_b = design_b;
  result.designed = true;
  finish_sizing(result);
  return result;
}

namespace {
double known_or_infinite(const Extreme& e) { return e.known ? e.value : std::numeric_limits<double>::infinity(); }
}  // namespace

PopulationSizing size_population(const std::vector<const SizingResult*>& motors, double yield) {
  PopulationSizing p;
  p.motors = motors.size();
  p.yield = yield;
  p.needed = static_cast<std::size_t>(std::ceil(yield * static_cast<double>(motors.size()) - 1e-9));
  std::vector<std::optional<std::pair<double, double>>> spans;
  // A worst case that was never found (no row had it, e.g. no parallel design) is not within any
  // value: +inf, so that too many of them leave the figure not reached.
  using Pick = double (*)(const SizingSummary&);
  const std::pair<PopulationFigure PopulationSizing::*, Pick> figures[] = {
      {&PopulationSizing::current_rms_a, [](const SizingSummary& s) { return known_or_infinite(s.current_rms_a); }},
      {&PopulationSizing::current_peak_a, [](const SizingSummary& s) { return known_or_infinite(s.current_peak_a); }},
      {&PopulationSizing::apparent_power_va,
       [](const SizingSummary& s) { return known_or_infinite(s.apparent_power_va); }},
      {&PopulationSizing::power_w, [](const SizingSummary& s) { return known_or_infinite(s.power_w); }},
      {&PopulationSizing::stator_heat_w, [](const SizingSummary& s) { return known_or_infinite(s.stator_heat_w); }},
      {&PopulationSizing::parallel_current_amplitude_a,
       [](const SizingSummary& s) { return known_or_infinite(s.parallel_current_amplitude_a); }},
      {&PopulationSizing::parallel_phase_abs_deg,
       [](const SizingSummary& s) { return known_or_infinite(s.parallel_phase_abs_deg); }},
      {&PopulationSizing::series_source_voltage_v,
       [](const SizingSummary& s) { return known_or_infinite(s.series_source_voltage_v); }},
  };
  std::vector<std::vector<double>> values(std::size(figures));
  for (const SizingResult* m : motors) {
    const bool whole = m != nullptr && !m->rows.empty() && m->summary.sized == m->rows.size();
    if (!whole) {
      spans.emplace_back(std::nullopt);
      continue;
    }
    ++p.sized;
    double low = m->rows.front().frequency_hz, high = low;
    for (const SizingRow& r : m->rows) {
      low = std::min(low, r.frequency_hz);
      high = std::max(high, r.frequency_hz);
    }
    spans.emplace_back(std::pair{low, high});
    for (std::size_t k = 0; k < std::size(figures); ++k) values[k].push_back(figures[k].second(m->summary));
  }
  const FrequencyBand band = narrowest_band(spans, yield);
  p.oscillator_reached = band.reached;
  p.oscillator_low_hz = band.low_hz;
  p.oscillator_high_hz = band.high_hz;
  p.oscillator_covered = band.covered;
  for (std::size_t k = 0; k < std::size(figures); ++k) {
    std::vector<double>& v = values[k];
    std::sort(v.begin(), v.end());
    PopulationFigure& f = p.*(figures[k].first);
    // The needed-th smallest worst case: that many motors stay within it.
    f.reached = p.needed >= 1 && p.needed <= v.size() && std::isfinite(v[p.needed - 1]);
    f.value = f.reached ? v[p.needed - 1] : 0.0;
  }
  return p;
}

}  // namespace swum
