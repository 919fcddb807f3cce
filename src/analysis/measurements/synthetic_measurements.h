// Measurement-like data from any parameter set (effects enabled or not): the model's
// prediction of each point (measured_point_model.h, sweeps by continuation) with the noise of
// a real bench: multiplicative Gaussian noise value * (1 + noise N(0,1)), an additive sensor
// floor (a laser vibrometer or encoder reads a few mm/s or nm even at standstill) and drive
// frequency jitter (each reading taken at frequency_hz + jitter N(0,1), recorded as
// frequency_hz); optionally repeated. `swum synth` and the tests use it.
#pragma once

#include <cstdint>
#include <functional>
#include <span>

#include "analysis/measurements/measured_point_model.h"
#include "analysis/measurements/measurements.h"

namespace swum {

struct SynthOptions {
  double relative_noise = 0.02;
  // Additive noise floor (standard deviation) per quantity, in its unit: speed mm/s, tip
  // amplitudes um. 0: none.
  double speed_floor_mm_s = 0.0;
  double amplitude_floor_um = 0.0;
  double frequency_jitter_hz = 0.0;  // standard deviation of the drive frequency error
  std::uint64_t seed = 1;
  int repeats = 1;  // readings per point (same operating point and time_s)
  std::array<bool, kQuantityCount> quantities{true, true, true};
  PredictionOptions prediction;
};

// Called with each row of the result, in the result's order, as soon as it is final (from the
// tasks of `parallel`, one call at a time); what it throws stops the synthesis.
using SynthRowReady = std::function<void(const Measurement& row)>;

// `points` carry amplitude_v, frequency_hz, load_n and optionally time_s and sweep (their values are
// ignored). Diverged points are left out. The result keeps the points' order (repeats adjacent;
// with frequency jitter each repeat is a reading of its own, at its own jittered frequency).
[[nodiscard]] MeasurementSet synthesize_measurements(const MotorParameters& parameters,
                                                     std::span<const Measurement> points, const SynthOptions& options,
                                                     const ParallelFor& parallel, const SynthRowReady& row_ready = {});

// The columns synthesize_measurements gives these points (a set without rows): a file's header
// can be written before the first row is ready.
[[nodiscard]] MeasurementSet synthesis_layout(std::span<const Measurement> points, const SynthOptions& options);

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
