// Choosing the drive frequency for one voltage from a measured speed-vs-frequency curve.
// Pure: no I/O. The rule is documented in docs/host.md ("swum pick").
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace swum {

struct CurveSample {
  double frequency_hz = 0.0;
  double speed_mm_s = 0.0;
  bool ok = true;             // false: the point failed (diverged, unsettled, no answer)
  double spread_mm_s = -1.0;  // measured spread of the speed at this point; < 0 = unknown
};

struct PickOptions {
  double min_margin_hz = 0.0;  // user's floor for the high-side margin
  double naive_frequency_hz = 40400.0;
};

struct PickResult {
  bool decided = false;
  std::string reason;              // why this frequency, or why undecided
  double frequency_hz = 0.0;       // recommended (a measured grid point)
  double speed_mm_s = 0.0;         // measured speed there
  double peak_frequency_hz = 0.0;  // highest speed on the branch reached from above
  double peak_speed_mm_s = 0.0;
  double margin_hz = 0.0;  // frequency - peak >= margin
  double grid_step_hz = 0.0;
  double noise_mm_s = 0.0;
  std::optional<double> collapse_hz;       // first point below the peak that collapsed
  std::optional<double> naive_speed_mm_s;  // interpolated at naive_frequency_hz
};

/// Picks the operating frequency of one curve (any order; duplicates averaged).
PickResult pick_operating_point(std::vector<CurveSample> samples, const PickOptions& options = {});

// The pick at one drive voltage (swum pick, swum population: a row per voltage).
struct VoltagePick {
  double amplitude_v = 0.0;
  PickResult result;
};

}  // namespace swum
