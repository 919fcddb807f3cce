// Synthetic free-stator amplitude data (the round-trip test of the identification and the
// paper's Figs. 7-8 with a known parameter set): harmonic balance on the branch a voltage
// up-sweep follows at each frequency, times (1 + relative_noise * N(0,1)) from a seeded RNG.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "analysis/free_stator/amplitude_measurement.h"
#include "analysis/free_stator/harmonic_balance.h"
#include "model/parameters.h"

namespace swum {

struct SyntheticAmplitudeOptions {
  double relative_noise = 0.0;  // standard deviation of the multiplicative Gaussian noise
  std::uint64_t seed = 1;       // std::mt19937_64 + Box-Muller (same numbers on every platform)
  bool normal = true;           // fill tip_normal_um
  bool tangential = true;       // fill tip_tangential_um
  HarmonicBalanceOptions harmonic_balance;
};

// Grid amplitudes_v x frequencies (voltages swept upwards in the given order at each frequency).
// Points where the sweep has no stable branch are left out.
[[nodiscard]] std::vector<AmplitudeMeasurement> synthesize_amplitudes(const MotorParameters& parameters,
                                                                      std::span<const double> amplitudes_v,
                                                                      std::span<const double> frequencies_hz,
                                                                      const SyntheticAmplitudeOptions& options = {});

}  // namespace swum
