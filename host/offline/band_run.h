// `swum band` on this machine: the command-line checks of a band grid and the band's chains on
// this machine's cores. The algorithm (down-sweeps, picks, summary) is src/'s
// (analysis/operating_point/operating_band.h).
#pragma once

#include <string>
#include <vector>

#include "analysis/operating_point/operating_band.h"
#include "model/parameters.h"

namespace swum::host {

// Throws std::invalid_argument naming the option (--amplitude-v, --frequency-hz, --load as check_grid;
// --temperature-rise-k 0..300 K; --margin-hz 0..10000 Hz; --jobs 0..1024) of a value no band can
// use.
void check_band_grid(const BandGrid& grid, int jobs = 0);

// A rise other than 0 needs the thermal effect: throws std::invalid_argument naming
// --temperature-rise-k and `parameters_source` (the file) when it is off.
void check_band_thermal(const BandGrid& grid, const MotorParameters& parameters, const std::string& parameters_source);

// operating_band on `jobs` threads (0 = all cores); the rows do not depend on `jobs`.
std::vector<BandRow> run_operating_band(const MotorModel& model, const BandGrid& grid, int jobs,
                                        const BandPointDone& point_done = {});

}  // namespace swum::host
