// What `swum track-report` prints and draws (docs/host.md): per tracking run the share of the
// best speed available at each moment, as a table or as JSON (--json), and four plots over
// device time (--plot-dir). The shares themselves: track/track_report.h.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "track/track_report.h"

namespace swum::host {

/// One object per run with its final values and its blocks (pretty, ordered keys, '\n' at
/// the end).
std::string tracking_json(const std::vector<TrackRunSummary>& summaries);

/// A header line and one aligned line per run.
std::string tracking_text(const std::vector<TrackRunSummary>& summaries);

/// tracking_share.png, tracking_frequency.png, tracking_speed.png and tracking_temperature.png
/// in `dir` (which must exist). `amplitude_v`: the runs' drive amplitude (titles); `ambient_c`: the
/// ambient the best speed's temperature rise is measured from.
void write_tracking_plots(const std::filesystem::path& dir, const std::vector<TrackSeries>& runs,
                          const std::vector<TrackRunSummary>& summaries, const BestSpeedCurve& best, double amplitude_v,
                          double ambient_c);

}  // namespace swum::host
