#include "analysis/synthetic_measurements.h"

#include <cmath>
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

MeasurementSet synthesize_measurements(const MotorParameters& parameters,
                                       std::span<const Measurement> points,
                                       const SynthOptions& options, const ParallelFor& parallel) {
  const std::vector<Predictions> predicted =
      predict_points(std::span(&parameters, 1), points, options.prediction, parallel);
  MeasurementSet set;
  set.has_quantity = options.quantities;
  set.has_time = !points.empty();
  for (const Measurement& m : points) set.has_time &= m.time_s.has_value();
  GaussianNoise noise(options.seed);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const PredictedPoint& p = predicted[0][i];
    if (!p.ok) continue;
    for (int k = 0; k < std::max(1, options.repeats); ++k) {
      Measurement row = points[i];
      if (!set.has_time) row.time_s.reset();
      for (Quantity q : kQuantities) {
        const std::size_t j = static_cast<std::size_t>(q);
        const double e = noise.next();
        row.values[j] = options.quantities[j]
                            ? std::optional<double>(p.value(q) * (1.0 + options.relative_noise * e))
                            : std::nullopt;
      }
      set.rows.push_back(row);
    }
  }
  return set;
}

}  // namespace swum
