// The amplifier's output network of one phase (docs/amplifier.md): a source of voltage V_s
// behind a series impedance Z_s = R_s + j w L_s, and at the motor's terminals, in parallel with
// the phase, an optional inductor L_p. The phase is its clamped capacitance C0 (the stator's
// clamped_capacitance_nf) in parallel with the motional current I_m of the modes, so with
// Y_p = j w C0 + 1/(j w L_p) (the parallel inductor's term only when there is one):
//   V_s = Z_s I_amp + V,  I_amp = Y_p V + I_m   =>   V = (V_s - Z_s I_m) / (1 + Z_s Y_p).
// Phasors throughout are sine phasors: x(t) = Im(X e^{j theta}) = Re X sin theta + Im X cos theta,
// theta the drive phase (V_A's source voltage is A sin theta: phasor A, real). Evaluated by
// MotorSimulator once per housekeeping block (64 steps), never in a step.
#pragma once

#include <complex>
#include <string>
#include <string_view>

#include "model/parameters.h"

namespace swum {

using Phasor = std::complex<double>;

struct OutputNetwork {
  double source_resistance_ohm = 0.0;
  double series_inductance_h = 0.0;
  double parallel_inductance_h = 0.0;  // 0 = no parallel inductor
  double clamped_capacitance_f = 0.0;  // C0 of the phase (the stator's)

  // Ideal source: the terminal voltage is the source voltage and the network does nothing.
  [[nodiscard]] bool ideal() const {
    return source_resistance_ohm == 0.0 && series_inductance_h == 0.0 && parallel_inductance_h == 0.0;
  }
  [[nodiscard]] Phasor series_impedance_ohm(double angular_frequency_rad_s) const {
    return {source_resistance_ohm, angular_frequency_rad_s * series_inductance_h};
  }
  // j w C0 + 1/(j w L_p) (S); at w = 0 the inductor's term is left out (no drive, no current).
  [[nodiscard]] Phasor parallel_admittance_siemens(double angular_frequency_rad_s) const {
    double b = angular_frequency_rad_s * clamped_capacitance_f;
    if (parallel_inductance_h > 0.0 && angular_frequency_rad_s > 0.0) {
      b -= 1.0 / (angular_frequency_rad_s * parallel_inductance_h);
    }
    return {0.0, b};
  }
  // 1 + Z_s Y_p: the divider of the idle network (no motional current). Near 0 the terminal
  // voltage of the idle network diverges.
  [[nodiscard]] Phasor divider(double angular_frequency_rad_s) const {
    return 1.0 + series_impedance_ohm(angular_frequency_rad_s) * parallel_admittance_siemens(angular_frequency_rad_s);
  }
  // V = (V_s - Z_s I_m) / (1 + Z_s Y_p).
  [[nodiscard]] Phasor terminal_voltage_v(double angular_frequency_rad_s, Phasor source_v,
                                          Phasor motional_current_a) const {
    return (source_v - series_impedance_ohm(angular_frequency_rad_s) * motional_current_a) /
           divider(angular_frequency_rad_s);
  }
  // I_amp = Y_p V + I_m: what leaves the amplifier (C0's current, the parallel inductor's and the
  // motional current; equal to (V_s - V)/Z_s whenever Z_s != 0).
  [[nodiscard]] Phasor amplifier_current_a(double angular_frequency_rad_s, Phasor terminal_v,
                                           Phasor motional_current_a) const {
    return parallel_admittance_siemens(angular_frequency_rad_s) * terminal_v + motional_current_a;
  }
};

// The network's state of one phase per volt of the source phasor V_s: the terminal voltage
// g = V/V_s (the gain the steps apply), the series branch's current I_s/V_s and the parallel
// inductor's I_Lp/V_s. Ideal: g = 1, no currents.
struct NetworkPhase {
  Phasor gain{1.0, 0.0};
  Phasor series{};
  Phasor parallel{};
};

// One block of the network's envelope (the slowly varying phasors of V, I_s, I_Lp; x = Im(X e^{j
// theta}), so d/dt -> d/dt + j w) by implicit Euler over `block_s`, the motional current held:
//   L_s (I_s' + j w I_s) = V_s - R_s I_s - V,   L_p (I_Lp' + j w I_Lp) = V,
//   C0 (V' + j w V) = I_s - I_Lp - I_m.
// Its fixed point is the steady state V = (V_s - Z_s I_m)/(1 + Z_s Y_p); implicit Euler is stable
// for any block, so a network faster than a block is solved algebraically and a slow one (a series
// inductance near resonance with C0) rings in over its own time constant instead of overshooting.
// Without a series impedance V = V_s. Returns false (state unchanged) when the new gain is not
// finite or above `largest_gain`; a zero source: the state is kept (no phasor per volt).
bool step_network(const OutputNetwork& network, double angular_frequency_rad_s, double block_s, Phasor source_v,
                  Phasor motional_current_a, NetworkPhase& state, double largest_gain = 1000.0);

// What the amplifier of one phase delivers (MotorSimulator::amplifier_readings): the amplitude of
// its output current (A, zero-to-peak) and its phase relative to the source voltage (deg in
// (-180, 180], + = the current leads), and the terminal voltage amplitude of the phase (V) and its
// phase relative to the source voltage.
struct AmplifierPhaseReadings {
  double current_a = 0.0;
  double current_phase_deg = 0.0;
  double terminal_amplitude_v = 0.0;
  double terminal_phase_deg = 0.0;
};
struct AmplifierReadings {
  AmplifierPhaseReadings a, b;
};

// The sine phasor of a signal x(t) = Im(X e^{j theta}) from its value and derivative at phase
// theta (exact for a sinusoid at w): X = (x sin + (x'/w) cos) + j (x cos - (x'/w) sin).
[[nodiscard]] inline Phasor sine_phasor(double value, double derivative_over_w, double sin_theta, double cos_theta) {
  return {value * sin_theta + derivative_over_w * cos_theta, value * cos_theta - derivative_over_w * sin_theta};
}

// The smallest |1 + Z_s Y_p| over [low_hz, high_hz] and where (a fine grid, then the exact
// zero of the lossless case): load-time checks of a network (parameter file, MotorModel).
struct DividerMinimum {
  double magnitude = 0.0;
  double frequency_hz = 0.0;
};
[[nodiscard]] DividerMinimum smallest_divider(const OutputNetwork& network, double low_hz, double high_hz);

// The network of a parameter set: [amplifier], with the amplifier_droop effect's R_s added to the
// source resistance when that effect is on, and the stator's C0.
[[nodiscard]] OutputNetwork make_output_network(const MotorParameters& parameters);

// The band the load-time check covers: 0.9 x the lower to 1.1 x the higher of the two modes'
// target frequencies (every drive frequency of a sweep, pick or band lies inside it).
struct NetworkCheckBand {
  double low_hz = 0.0;
  double high_hz = 0.0;
};
[[nodiscard]] NetworkCheckBand network_check_band(const MotorParameters& parameters);

// Below this |1 + Z_s Y_p| somewhere in the band (the idle terminal voltage more than 1000 times
// the source's: a lossless series resonance with C0) a parameter set is refused.
inline constexpr double kSmallestNetworkDivider = 1e-3;

// "" when the network is usable; else a one-line problem naming the keys (validate_parameters).
[[nodiscard]] std::string check_output_network(const MotorParameters& parameters);

}  // namespace swum
