// What `swum pick` prints and writes (docs/host.md): per voltage and load the picked frequency,
// its speed against the naive 40.4 kHz, the drift of the peak; as text lines, as a JSON list
// (--json) and as the amplitude_v,load_n,frequency_hz schedule (--schedule). Its plots: pick_plots.h.
#pragma once

#include <string>
#include <vector>

#include "output/reports/operating_point/pick_plots.h"

namespace swum::host {

/// The speed gain over the naive frequency in percent; NaN when undecided or unknown.
double pick_gain_percent(const PickResult& r);

/// One line per (voltage, load): "  40 V, 0 N: run at 40150 Hz, ..." or "  40 V, 0 N: undecided:
/// <reason>". Drift is measured from the peak of the lowest decided voltage at the same load.
std::string pick_text(const std::vector<VoltagePick>& picks);

/// The same as a JSON list (pretty, ordered keys, '\n' at the end); null where undecided.
std::string pick_json(const std::vector<VoltagePick>& picks);

/// "amplitude_v,load_n,frequency_hz\n" and one row per decided (voltage, load).
std::string pick_schedule_csv(const std::vector<VoltagePick>& picks);

}  // namespace swum::host
