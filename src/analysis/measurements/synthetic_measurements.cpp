#include "analysis/measurements/synthetic_measurements.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>
#include <optional>

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

MeasurementSet synthesis_layout(std::span<const Measurement> points, const SynthOptions& options) {
  MeasurementSet set;
  set.has_quantity = options.quantities;
  set.has_time = !points.empty();
  set.has_sweep = !points.empty();
  for (const Measurement& m : points) {
    set.has_time &= m.time_s.has_value();
    set.has_sweep &= m.sweep.has_value();
  }
  return set;
}

MeasurementSet synthesize_measurements(const MotorParameters& parameters, std::span<const Measurement> points,
                                       const SynthOptions& options, const ParallelFor& parallel,
                                       const SynthRowReady& row_ready) {
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
  MeasurementSet set = synthesis_layout(points, options);
  const std::size_t n = readings.size();
  // A reading's row is final once its prediction, the predictions of every reading before it in
  // session order (sweep ids, below) and the rows before it in the file (the noise stream runs
  // in file order) are: rows go out in file order as the predictions come in, in any order.
  std::mutex mutex;
  std::vector<PredictedPoint> predicted(n);
  std::vector<char> have(n, 0), in_session(n, 0);
  const std::vector<std::size_t> order = session_order(readings);
  std::size_t next_in_session = 0, next_in_file = 0;
  bool failed = false;
  // A diverged reading is left out, and it handed the rest state on to the next reading of its
  // sweep (in session order): the rest of that sweep gets a fresh id, so a prediction of the file
  // starts it from rest too (as a device restarts a curve after a fault).
  int next_sweep = 0;
  for (const Measurement& m : points) next_sweep = std::max(next_sweep, m.sweep.value_or(-1) + 1);
  std::vector<std::optional<int>> sweep_of(n);
  std::map<int, int> renamed;
  auto sweep_in_session = [&](std::size_t r) {
    sweep_of[r] = readings[r].sweep;
    if (!readings[r].sweep) return;
    if (!predicted[r].ok) {
      renamed[*readings[r].sweep] = next_sweep++;
    } else if (const auto it = renamed.find(*readings[r].sweep); it != renamed.end()) {
      sweep_of[r] = it->second;
    }
  };
  auto row_in_file = [&](std::size_t r) {
    const PredictedPoint& p = predicted[r];
    const Measurement& point = points[r / static_cast<std::size_t>(repeats)];
    if (!p.ok) return;
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
    if (row_ready) row_ready(set.rows.back());
  };
  (void)predict_points(std::span(&parameters, 1), readings, options.prediction, parallel,
                       [&](std::size_t, std::size_t r, const PredictedPoint& p) {
                         const std::lock_guard lock(mutex);
                         if (failed) return;  // row_ready threw: the batch is stopping
                         predicted[r] = p;
                         have[r] = 1;
                         for (; next_in_session < n && have[order[next_in_session]]; ++next_in_session) {
                           sweep_in_session(order[next_in_session]);
                           in_session[order[next_in_session]] = 1;
                         }
                         try {
                           for (; next_in_file < n && in_session[next_in_file]; ++next_in_file) {
                             row_in_file(next_in_file);
                           }
                         } catch (...) {
                           failed = true;
                           throw;
                         }
                       });
  return set;
}

}  // namespace swum
