// Choosing the drive frequency for one voltage from a measured speed-vs-frequency curve: the one
// definition of the drift-aware operating point (`swum pick` from a table, the model or a device,
// `swum band`, `swum population`, the demo; `swum track` holds peak + the same default margin).
// Pure: no I/O. The rule and the default margin are argued in docs/host.md ("The operating point").
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

// The default floor of the margin above the softening peak, in every command (--margin-hz): the
// distance kept from the fold below the peak for what moves the peak up towards the drive (a
// cooler stator, a lighter load, a lower amplitude) and for the peak's uncertainty; warming moves
// the peak down, away from the drive (docs/host.md, "The operating point").
inline constexpr double kDefaultMarginHz = 100.0;

// The default frequency grid of a model or device curve (--frequency-hz START:STOP:STEP, Hz): from
// above every cold peak of the calibrated motor down past the collapse of a stator ~100 K warm.
inline constexpr const char* kDefaultFrequencyGrid = "38000:41500:25";

struct PickOptions {
  double min_margin_hz = kDefaultMarginHz;  // user's floor for the high-side margin
  double naive_frequency_hz = 40400.0;
};

struct PickResult {
  bool decided = false;
  std::string reason;              // why this frequency, or why undecided
  double frequency_hz = 0.0;       // recommended: peak + margin, up to the next whole Hz
  double speed_mm_s = 0.0;         // interpolated there between the measured points either side
  double peak_frequency_hz = 0.0;  // the peak of the branch reached from above, finer than the grid
  double peak_speed_mm_s = 0.0;    // the best measured speed (at the grid point nearest the peak)
  double margin_hz = 0.0;          // frequency - peak >= margin
  double grid_step_hz = 0.0;
  double noise_mm_s = 0.0;
  std::optional<double> collapse_hz;       // first point below the peak that collapsed
  std::optional<double> naive_speed_mm_s;  // interpolated at naive_frequency_hz
};

/// Picks the operating frequency of one curve (any order; duplicates averaged).
PickResult pick_operating_point(std::vector<CurveSample> samples, const PickOptions& options = {});

// The pick at one drive voltage and load (swum pick: a row per voltage and load, as swum band's
// rows; swum population: a row per voltage).
struct VoltagePick {
  double amplitude_v = 0.0;
  PickResult result;
  double load_n = 0.0;
};

}  // namespace swum
