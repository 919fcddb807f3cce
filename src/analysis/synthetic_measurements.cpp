#include "analysis/synthetic_measurements.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

namespace swum {

std::uint64_t GaussianNoise::bits() {
  // splitmix64: portable and well mixed for consecutive seeds.
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double GaussianNoise::next() {
  if (have_spare_) {
    have_spare_ = false;
    return spare_;
  }
  const double u1 = (static_cast<double>(bits() >> 11) + 0.5) * 0x1.0p-53;  // (0, 1)
  const double u2 = static_cast<double>(bits() >> 11) * 0x1.0p-53;
  const double radius = std::sqrt(-2.0 * std::log(u1));
  spare_ = radius * std::sin(2.0 * std::numbers::pi * u2);
  have_spare_ = true;
  return radius * std::cos(2.0 * std::numbers::pi * u2);
}

MeasurementSet synthesize_measurements(const MotorParameters& parameters, std::span<const Measurement> points,
                                       const SynthOptions& options, const ParallelFor& parallel) {
  const int repeats = std::max(1, options.repeats);
  GaussianNoise noise(options.seed);
  // Every reading is a point of its own for the model (repeats follow each other in time and,
  // within a sweep, by continuation); its drive frequency carries the jitter.
  std::vector<Measurement> readings;
  readings.reserve(points.size() * static_cast<std::size_t>(repeats));
  GaussianNoise jitter(options.seed ^ 0x6A09E667F3BCC909ULL);  // own stream: jitter 0 keeps old data
  for (const Measurement& m : points) {
    for (int k = 0; k < repeats; ++k) {
      Measurement reading = m;
      if (options.frequency_jitter_hz > 0.0) reading.frequency_hz += options.frequency_jitter_hz * jitter.next();
      readings.push_back(reading);
    }
  }
  const std::vector<Predictions> predicted = predict_points(std::span(&parameters, 1), readings, options.prediction,
                                                            parallel);
  MeasurementSet set;
  set.has_quantity = options.quantities;
  set.has_time = !points.empty();
  set.has_sweep = !points.empty();
  for (const Measurement& m : points) {
    set.has_time &= m.time_s.has_value();
    set.has_sweep &= m.sweep.has_value();
  }
  // A diverged reading is left out, and it handed the rest state on to the next reading of its
  // sweep (in session order): the rest of that sweep gets a fresh id, so a prediction of the file
  // starts it from rest too (as a device restarts a curve after a fault).
  int next_sweep = 0;
  for (const Measurement& m : points) next_sweep = std::max(next_sweep, m.sweep.value_or(-1) + 1);
  std::vector<std::optional<int>> sweep_of(readings.size());
  std::map<int, int> renamed;
  for (std::size_t r : session_order(readings)) {
    sweep_of[r] = readings[r].sweep;
    if (!readings[r].sweep) continue;
    if (!predicted[0][r].ok) {
      renamed[*readings[r].sweep] = next_sweep++;
    } else if (const auto it = renamed.find(*readings[r].sweep); it != renamed.end()) {
      sweep_of[r] = it->second;
    }
  }
  for (std::size_t r = 0; r < readings.size(); ++r) {
    const PredictedPoint& p = predicted[0][r];
    const Measurement& point = points[r / static_cast<std::size_t>(repeats)];
    if (!p.ok) continue;
    Measurement row = point;  // the nominal frequency: what the user set
    row.sweep = sweep_of[r];
    if (!set.has_time) row.time_s.reset();
    if (!set.has_sweep) row.sweep.reset();
    for (Quantity q : kQuantities) {
      const std::size_t j = static_cast<std::size_t>(q);
      const double e = noise.next();
      const double floor = q == Quantity::speed ? options.speed_floor_mm_s : options.amplitude_floor_um;
      const double f = floor > 0.0 ? floor * noise.next() : 0.0;
      double value = p.value(q) * (1.0 + options.relative_noise * e) + f;
      if (q != Quantity::speed) value = std::abs(value);  // an amplitude reads >= 0
      row.values[j] = options.quantities[j] ? std::optional<double>(value) : std::nullopt;
    }
    set.rows.push_back(row);
  }
  return set;
}

}  // namespace swum
