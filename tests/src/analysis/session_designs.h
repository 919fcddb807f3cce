// Sessions shaped like users' data (issue 11), shared by the discrepancy tests: the covering
// designs' operating points, a bench's noise, the noise-free truth and the held-out gap to it.
#pragma once

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include "analysis/measurements/synthetic_measurements.h"
#include "discrepancy_test_support.h"
#include "thread_pool_for.h"

namespace swum::test {

struct Design {
  const char* name;
  bool through_peak;  // 39.0-41.0 kHz (crosses the softening peak) or 40.0-41.0 kHz
  bool shuffled;      // voltages in shuffled order
  int points;         // operating points (before repeats)
  int repeats;        // readings per point
  bool sweeps;        // continuous downward sweeps (sweep column) or spot points from rest
  bool speed_only;    // a board without a vibrometer
};

inline double uniform(std::mt19937_64& rng, double a, double b) {
  return a + (b - a) * static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// The operating points of a design, in session order, one reading every 2 s.
inline std::vector<Measurement> design_points(const Design& d, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double f_low = d.through_peak ? 39000.0 : 40000.0;
  const double f_high = 41000.0;
  // Curves of `per_curve` frequencies; voltages spread over 100-400 V.
  const int per_curve = d.points >= 200 ? 20 : 10;
  const int curves = std::max(1, d.points / per_curve);
  std::vector<double> voltages;
  for (int c = 0; c < curves; ++c) voltages.push_back(std::round(100.0 + 300.0 * (c + 0.5) / curves));
  if (d.shuffled) std::shuffle(voltages.begin(), voltages.end(), rng);
  std::vector<Measurement> points;
  double time_s = 0.0;
  for (int c = 0; c < curves; ++c) {
    const double load = d.sweeps ? static_cast<double>(c % 4) : 0.0;
    for (int k = 0; k < per_curve; ++k) {
      Measurement m;
      m.amplitude_v = voltages[static_cast<std::size_t>(c)];
      // Sweeps go down from the top (as `swum sweep` on a device); spot points in any order.
      const double step = (f_high - f_low) / (per_curve - 1);
      m.frequency_hz = d.sweeps ? f_high - step * k : std::round(uniform(rng, f_low, f_high));
      m.load_n = d.sweeps ? load : static_cast<double>(rng() % 4);
      m.time_s = time_s;
      if (d.sweeps) m.sweep = c;
      time_s += 2.0 * d.repeats;
      points.push_back(m);
    }
  }
  return points;
}

// 2.5 % multiplicative noise and a sensor floor; drive-frequency jitter only where asked (the
// noise-only sessions): a jittered frequency biases a fitted value near steep parts of the curve
// (errors in the variables), which no standard error of the fit covers (docs/discrepancy.md,
// known limits).
inline SynthOptions bench_noise(const Design& d, std::uint64_t seed, double jitter_hz = 0.0) {
  SynthOptions o;
  o.relative_noise = 0.025;
  o.speed_floor_mm_s = 2.0;
  o.amplitude_floor_um = 0.005;
  o.frequency_jitter_hz = jitter_hz;
  o.seed = seed;
  o.repeats = d.repeats;
  if (d.speed_only) o.quantities = {true, false, false};
  return o;
}

// Noise-free readings of the same points: the truth the gap is measured against.
inline MeasurementSet clean_readings(const MotorParameters& p, const std::vector<Measurement>& points,
                                     const Design& d) {
  SynthOptions o = bench_noise(d, 1);
  o.relative_noise = 0.0;
  o.speed_floor_mm_s = 0.0;
  o.amplitude_floor_um = 0.0;
  o.frequency_jitter_hz = 0.0;
  o.repeats = 1;
  return synthesize_measurements(p, points, o, two_thread_for);
}

// RMS relative gap between predictions of the data's rows and the noise-free truth of their
// operating points, on the held-out rows.
inline double held_out_gap_to_truth(const MeasurementSet& data, const MeasurementSet& truth,
                                    const Predictions& predicted, const std::vector<bool>& held_out) {
  std::map<std::tuple<double, double, double>, const Measurement*> truth_of;
  for (const Measurement& m : truth.rows) truth_of[{m.amplitude_v, m.frequency_hz, m.load_n}] = &m;
  MeasurementSet reference = data;
  for (Measurement& m : reference.rows) {
    const Measurement* t = truth_of.at({m.amplitude_v, m.frequency_hz, m.load_n});
    for (Quantity q : kQuantities) {
      if (m.value(q)) m.values[static_cast<std::size_t>(q)] = t->value(q);
    }
  }
  return held_out_gap(reference, predicted, held_out);
}

}  // namespace swum::test
