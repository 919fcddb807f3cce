// The matching network of one phase at a design point (docs/amplifier.md, "Matching"): pure
// formulas from the phase's terminal admittance Y = G + jB (A/V) measured at the target terminal
// voltage amplitude V and angular frequency w, and its clamped capacitance C0. What
// [amplifier] parallel_inductance_uh / series_inductance_uh to set, and what the amplifier then
// delivers. Throws std::invalid_argument (one line) when a design point admits no such network.
#pragma once

#include <complex>

namespace swum {

struct MatchingDesignPoint {
  std::complex<double> admittance_siemens;  // Y = G + jB of the phase at the design point (+B: capacitive)
  double amplitude_v = 0.0;                 // target terminal voltage amplitude V (zero-to-peak)
  double angular_frequency_rad_s = 0.0;
  double clamped_capacitance_f = 0.0;  // C0 of the phase
};

// Y from an amplifier's reading of one phase: current amplitude I (A) at voltage amplitude V and
// the current's phase relative to the voltage (deg, + = leads): Y = (I/V) e^{j phase}.
[[nodiscard]] std::complex<double> admittance_from_reading(double current_a, double phase_deg, double amplitude_v);

// (a) The parallel inductance that cancels C0 alone: L = 1/(w^2 C0).
[[nodiscard]] double c0_compensating_inductance_h(double angular_frequency_rad_s, double clamped_capacitance_f);

// (b) The parallel inductance that cancels the whole susceptance at the design point,
// L = 1/(w B) (B > 0), and the amplifier current then: Y_total = G, I = G V, in phase (0 deg).
struct ParallelMatching {
  double inductance_h = 0.0;
  double amplifier_current_a = 0.0;
  double amplifier_current_phase_deg = 0.0;
};
[[nodiscard]] ParallelMatching parallel_matching(const MatchingDesignPoint& point);

// (c) Series matching (a series inductance alone) behind a source resistance R_s (0: an ideal
// amplifier): Z = 1/Y = R + jX, L_s = -X/w (X < 0), the amplifier output voltage for the target V,
// V_s = V (R + R_s)/|Z|, and its current V/|Z|, in phase with V_s (0 deg).
struct SeriesMatching {
  double inductance_h = 0.0;
  double amplifier_output_v = 0.0;
  double amplifier_current_a = 0.0;
  double amplifier_current_phase_deg = 0.0;
};
[[nodiscard]] SeriesMatching series_matching(const MatchingDesignPoint& point, double source_resistance_ohm = 0.0);

// The same inductors at another operating point (the network fixed, the motor detuned): what the
// amplifier delivers to a phase of admittance Y at voltage amplitude V (the phase voltage the
// reference of both phases' angles).
// With a parallel inductor L across the phase and the amplifier driving it directly: the
// amplifier's current V (Y + 1/(j w L)).
[[nodiscard]] std::complex<double> parallel_amplifier_current(std::complex<double> admittance_siemens,
                                                              double angular_frequency_rad_s, double amplitude_v,
                                                              double parallel_inductance_h);
// With a series inductor L_s between an ideal amplifier and the phase: the amplifier's output
// voltage V (1 + j w L_s Y) (its current is V Y).
[[nodiscard]] std::complex<double> series_source_voltage(std::complex<double> admittance_siemens,
                                                         double angular_frequency_rad_s, double amplitude_v,
                                                         double series_inductance_h);

}  // namespace swum
