// What `swum track` prints and draws besides its CSV rows (docs/host.md, "swum track"): the
// run's one-line summary and the plots of the run over device time (--plot-dir).
#pragma once

#include <string>
#include <vector>

#include "track/track_run.h"

namespace swum::host {

/// What the plots show: the rows kept in memory (a few numbers per cycle); NaN where a row
/// carries no temperature or no electrical reading.
struct TrackPlotSeries {
  std::vector<double> time_s, frequency_khz, speed_mm_s, temperature_c, phase_deg;
  void add(const TrackRow& r);
};

/// track_frequency.png and track_speed.png in `dir` (created), and track_temperature.png and
/// track_phase.png when any row carries those values.
void write_track_plots(const TrackPlotSeries& s, const std::string& dir, const std::string& method);

/// "N cycles (lockstep|wall time, method M) -> OUT; final F Hz; peak P Hz|none; phase set-point
/// D deg|none; C collapses\n".
std::string track_run_summary(const TrackRunResult& result, bool lockstep, const std::string& method,
                              const std::string& out_path);

}  // namespace swum::host
