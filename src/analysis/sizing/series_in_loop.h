// Series matching sized in the loop (docs/sizing.md, docs/amplifier.md "Matching"): the one-shot
// series design from the motor driven by an ideal source moves the motor (the network's step-up
// shifts the two phases' voltages differently), so the design is repeated on the admittance of
// the state it makes, in the time-domain simulator with the network as `[amplifier]`, until the
// target phase voltage holds. Both phases carry the same network (one [amplifier] section); the
// design follows phase A.
#pragma once

#include <complex>
#include <string>

#include "model/parameters.h"

namespace swum {

struct SeriesInLoop {
  bool converged = false;
  std::string reason;  // why not (a network refused at load, a diverged run, no convergence)
  int rounds = 0;
  double inductance_h = 0.0;
  double source_voltage_v = 0.0;  // the amplifier's output amplitude
  double source_resistance_ohm = 0.0;
  double terminal_a_v = 0.0, terminal_b_v = 0.0;  // the phase voltages reached
  double current_a_a = 0.0;                       // the amplifier's current of phase A (amplitude)
  double current_phase_a_deg = 0.0;               // against the amplifier's output voltage
};

// From `ideal` (no [amplifier] section) at frequency_hz: the series inductance and the amplifier's
// output voltage that bring phase A's terminal amplitude to target_v within `tolerance` (relative),
// behind the amplifier's source resistance (> 0: with 0 a series inductance resonating with C0
// is refused at load). admittance_siemens: phase A's admittance at the target voltage from an ideal
// source (the first round's design).
[[nodiscard]] SeriesInLoop series_matching_in_loop(const MotorParameters& ideal, double frequency_hz, double target_v,
                                                   std::complex<double> admittance_siemens,
                                                   double source_resistance_ohm, double tolerance = 0.02,
                                                   int max_rounds = 12);

}  // namespace swum
