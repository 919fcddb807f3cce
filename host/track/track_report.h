// `swum track-report`: how close tracking runs (swum track CSVs) stayed to the best speed
// available at each moment (docs/host.md, "swum track-report"). "Best" is the model's speed at
// the same margin above the speed peak at that moment's stator temperature: the rows of a
// `swum band` table (one voltage, one load, a grid of temperature rises), interpolated linearly
// in the rise. Pure: tables in, shares out; the command reads the files and writes the plots.
#pragma once

#include <string>
#include <vector>

namespace swum::host {

// One run's rows as the report needs them (swum track's CSV columns).
struct TrackSeries {
  std::string name;  // "phase", "speed", "fixed", or what --run named it
  std::vector<double> time_s, frequency_hz, speed_mm_s, stator_temperature_c;
};

// The reference: the best speed at peak + margin against the temperature rise (K), ascending.
struct BestSpeedCurve {
  std::vector<double> temperature_rise_k, speed_mm_s, frequency_hz, peak_frequency_hz;
  // Linear interpolation; outside the grid the nearest end (the caller checks coverage).
  [[nodiscard]] double speed_at(double rise_k) const;
  [[nodiscard]] double frequency_at(double rise_k) const;
  [[nodiscard]] double peak_frequency_at(double rise_k) const;
};

struct TrackBlock {
  double start_s = 0.0, end_s = 0.0;
  double mean_speed_mm_s = 0.0, mean_rise_k = 0.0, best_speed_mm_s = 0.0;
  double share = 0.0;      // mean speed / mean best over the block's rows
  double margin_hz = 0.0;  // mean of (frequency driven - the band's peak at the row's rise)
};

struct TrackRunSummary {
  std::string name;
  std::vector<TrackBlock> blocks;  // after the skipped start
  double min_share = 0.0;          // lowest block share
  double final_share = 0.0;        // the last block's
  double final_frequency_hz = 0.0;
  double final_margin_hz = 0.0;  // the last block's
  double final_rise_k = 0.0;
  double max_rise_k = 0.0;
};

// Each row's best speed is taken at its own temperature rise (stator_temperature_c minus
// ambient_c). Blocks of block_s from skip_s on. Bad options throw std::invalid_argument; data
// that cannot be compared (a rise outside the curve's grid: the band must cover the run; a row
// without temperature; no rows after skip_s) std::runtime_error, one line naming the run.
[[nodiscard]] TrackRunSummary summarise_track(const TrackSeries& run, const BestSpeedCurve& best, double ambient_c,
                                              double skip_s, double block_s);

// Readers: one-line std::runtime_error naming the file, line and column on bad input.
[[nodiscard]] TrackSeries read_track_csv(const std::string& path, const std::string& name);
// The rows of `path` (swum band's CSV) at amplitude_v and load_n that are decided, by rise.
[[nodiscard]] BestSpeedCurve read_band_csv(const std::string& path, double amplitude_v, double load_n);

}  // namespace swum::host
