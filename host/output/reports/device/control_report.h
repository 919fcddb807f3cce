// What `swum control` prints besides its CSV rows (docs/host.md, "swum control"): the run's
// one-line summary.
#pragma once

#include <string>

#include "control/speed_control.h"

namespace swum::host {

/// "N cycles at T mm/s (lockstep|wall time, recover CODES|none) -> OUT; mean |error| over the
/// last half E mm/s; F faults, R retries\n".
std::string control_run_summary(const SpeedControlResult& result, const SpeedControlSettings& settings, bool lockstep,
                                const std::string& out_path);

}  // namespace swum::host
