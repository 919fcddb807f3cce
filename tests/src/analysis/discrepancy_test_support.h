// Shared by the discrepancy tests: the calibrated motor and the held-out gap to a noise-free truth.
#pragma once

#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include "analysis/discrepancy/discrepancy.h"
#include "formats/parameter_file.h"
#include "test_paths.h"

namespace swum::test {

// A measured operating point at a session time, in a sweep (or none: a spot point).
inline Measurement measurement_at(double amplitude_v, double frequency_hz, double time_s, std::optional<int> sweep) {
  Measurement m;
  m.amplitude_v = amplitude_v;
  m.frequency_hz = frequency_hz;
  m.time_s = time_s;
  m.sweep = sweep;
  return m;
}

inline MotorParameters calibrated_motor() {
  std::ifstream in(swum::test::source_path("config/li2019.toml"));
  std::stringstream text;
  text << in.rdbuf();
  return parse_motor_parameters(text.str(), "config/li2019.toml");
}

// Whether a session named anything: a library effect, or a change of the base model (discovery.h).
inline bool names_something(const DiscrepancyResult& r) {
  const DiscoveryOutcome o = r.discovery.outcome;
  return !r.effects.empty() || o == DiscoveryOutcome::alone || o == DiscoveryOutcome::with_library ||
         o == DiscoveryOutcome::instead_of_library;
}

// RMS relative gap between a model's predictions and `truth` (the noise-free values of the same
// rows) on the held-out rows.
inline double held_out_gap(const MeasurementSet& truth, const Predictions& predicted,
                           const std::vector<bool>& held_out) {
  const ResidualModel model(truth, DiscrepancyOptions{}.floor_fraction);
  const std::vector<double> r = model.residuals(predicted);
  double sum = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    if (!held_out[model.slots()[k].row]) continue;
    sum += r[k] * r[k];
    ++n;
  }
  return std::sqrt(sum / n);
}

}  // namespace swum::test
