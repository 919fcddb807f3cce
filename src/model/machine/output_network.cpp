#include "model/machine/output_network.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace swum {

DividerMinimum smallest_divider(const OutputNetwork& network, double low_hz, double high_hz) {
  constexpr int kPoints = 2001;
  const auto at = [&](double f) { return network.divider(2.0 * std::numbers::pi * f); };
  DividerMinimum best{std::abs(at(low_hz)), low_hz};
  double previous_f = low_hz;
  double previous_re = at(low_hz).real();
  for (int i = 1; i < kPoints; ++i) {
    const double f = low_hz + (high_hz - low_hz) * i / (kPoints - 1);
    const Phasor d = at(f);
    if (std::abs(d) < best.magnitude) best = {std::abs(d), f};
    // A zero of the real part between two points (the lossless divider 1 - w L_s B_p is real):
    // the magnitude there, at the interpolated crossing.
    if ((previous_re > 0.0) != (d.real() > 0.0)) {
      const double crossing = previous_f + (f - previous_f) * previous_re / (previous_re - d.real());
      const double m = std::abs(at(crossing));
      if (m < best.magnitude) best = {m, crossing};
    }
    previous_f = f;
    previous_re = d.real();
  }
  return best;
}

bool step_network(const OutputNetwork& n, double w, double block_s, Phasor source_v, Phasor motional_current_a,
                  NetworkPhase& state, double largest_gain) {
  if (source_v == Phasor{} || !(block_s > 0.0)) return true;
  const Phasor m = motional_current_a / source_v;  // per volt of the source
  const Phasor j{0.0, 1.0};
  const double hold_c = n.clamped_capacitance_f / block_s;
  const Phasor c = hold_c + j * (w * n.clamped_capacitance_f);
  const bool has_parallel = n.parallel_inductance_h > 0.0;
  const double hold_p = has_parallel ? n.parallel_inductance_h / block_s : 0.0;
  const Phasor a_p = hold_p + j * (w * n.parallel_inductance_h);
  const Phasor z_s = n.series_impedance_ohm(w);
  NetworkPhase next;
  if (z_s == Phasor{}) {
    // The terminals are the source: the inductor's current rings in, the series current is the sum.
    next.gain = 1.0;
    next.parallel = has_parallel ? (1.0 + hold_p * state.parallel) / a_p : Phasor{};
    next.series = c * next.gain - hold_c * state.gain + next.parallel + m;
  } else {
    const double hold_s = n.series_inductance_h / block_s;
    const Phasor a_s = z_s + hold_s;
    // i_s' = (1 - g' + hold_s i_s)/a_s, i_p' = (g' + hold_p i_p)/a_p, c g' - hold_c g = i_s' - i_p' - m.
    const Phasor inv_p = has_parallel ? 1.0 / a_p : Phasor{};
    const Phasor lhs = c + 1.0 / a_s + inv_p;
    const Phasor rhs = hold_c * state.gain + (1.0 + hold_s * state.series) / a_s - hold_p * state.parallel * inv_p - m;
    next.gain = rhs / lhs;
    next.series = (1.0 - next.gain + hold_s * state.series) / a_s;
    next.parallel = has_parallel ? (next.gain + hold_p * state.parallel) * inv_p : Phasor{};
  }
  const double magnitude = std::abs(next.gain);
  if (!(magnitude <= largest_gain) || !std::isfinite(std::abs(next.series)) ||
      !std::isfinite(std::abs(next.parallel))) {
    return false;
  }
  state = next;
  return true;
}

OutputNetwork make_output_network(const MotorParameters& p) {
  OutputNetwork n;
  n.source_resistance_ohm = p.amplifier.source_resistance_ohm;
  if (p.effects.amplifier_droop.enabled) n.source_resistance_ohm += p.effects.amplifier_droop.source_resistance_ohm;
  n.series_inductance_h = p.amplifier.series_inductance_uh * 1e-6;
  n.parallel_inductance_h = p.amplifier.parallel_inductance_uh * 1e-6;
  n.clamped_capacitance_f = p.stator.clamped_capacitance_nf * 1e-9;
  return n;
}

NetworkCheckBand network_check_band(const MotorParameters& p) {
  const double low = std::min(p.stator.target_l1_frequency_hz, p.stator.target_b2_frequency_hz);
  const double high = std::max(p.stator.target_l1_frequency_hz, p.stator.target_b2_frequency_hz);
  return {0.9 * low, 1.1 * high};
}

std::string check_output_network(const MotorParameters& p) {
  const OutputNetwork n = make_output_network(p);
  if (n.ideal() || n.series_inductance_h == 0.0) return "";  // without L_s: |1 + R_s Y_p| >= 1
  const NetworkCheckBand band = network_check_band(p);
  const DividerMinimum m = smallest_divider(n, band.low_hz, band.high_hz);
  if (m.magnitude >= kSmallestNetworkDivider) return "";
  char text[400];
  std::snprintf(text, sizeof text,
                "amplifier.series_inductance_uh = %g with amplifier.source_resistance_ohm = %g, "
                "amplifier.parallel_inductance_uh = %g and stator.clamped_capacitance_nf = %g resonates at %.0f Hz, "
                "inside the motor's band %.0f..%.0f Hz (|1 + Z_s Y_p| = %.2g < %g): the terminal voltage diverges; "
                "add a source resistance or change the inductances",
                p.amplifier.series_inductance_uh, n.source_resistance_ohm, p.amplifier.parallel_inductance_uh,
                p.stator.clamped_capacitance_nf, m.frequency_hz, band.low_hz, band.high_hz, m.magnitude,
                kSmallestNetworkDivider);
  return text;
}

}  // namespace swum
