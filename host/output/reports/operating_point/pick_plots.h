// The three figures of `swum pick --plot-dir`: speed vs frequency per voltage with the picked
// points marked; picked (and peak) frequency vs voltage (paper Fig. 15); speed vs load at the
// picked and the naive frequency (paper Fig. 16).
#pragma once

#include <filesystem>
#include <utility>
#include <vector>

#include "analysis/operating_point/operating_point.h"
#include "output/sweep_table.h"

namespace swum::host {

void write_speed_vs_frequency_plot(const std::vector<SweepRow>& sweep, const std::vector<VoltagePick>& picks,
                                   double load_n, const std::filesystem::path& path);
void write_frequency_vs_voltage_plot(const std::vector<VoltagePick>& picks, double naive_frequency_hz,
                                     const std::filesystem::path& path);
// `load_rows`: rows at the picked and the naive frequency of each voltage, several loads.
void write_speed_vs_load_plot(const std::vector<SweepRow>& load_rows, const std::vector<VoltagePick>& picks,
                              double naive_frequency_hz, const std::filesystem::path& path);

}  // namespace swum::host
