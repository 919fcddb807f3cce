// Measurement-like data from any parameter set (effects enabled or not): the model's
// prediction of each point (measured_point_model.h) with multiplicative Gaussian noise
// value * (1 + noise * N(0,1)), optionally repeated. `swum synth` and the tests use it.
#pragma once

#include <cstdint>
#include <span>

#include "analysis/measured_point_model.h"
#include "analysis/measurements.h"

namespace swum {

struct SynthOptions {
  double relative_noise = 0.02;
  std::uint64_t seed = 1;
  int repeats = 1;  // readings per point (same operating point and time_s)
  std::array<bool, kQuantityCount> quantities{true, true, true};
  PredictionOptions prediction;
};

// `points` carry vpp, frequency_hz, load_n and optionally time_s (their values are ignored).
// Diverged points are left out. The result keeps the points' order (repeats adjacent).
[[nodiscard]] MeasurementSet synthesize_measurements(const MotorParameters& parameters,
                                                     std::span<const Measurement> points,
                                                     const SynthOptions& options,
                                                     const ParallelFor& parallel);

// Standard normal deviate from a 64-bit engine (Box-Muller; the same on every platform).
class GaussianNoise {
 public:
  explicit GaussianNoise(std::uint64_t seed) : state_(seed) {}
  double next();

 private:
  std::uint64_t bits();
  std::uint64_t state_;
  bool have_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace swum
