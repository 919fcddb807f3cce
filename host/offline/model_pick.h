// The picking step of `swum pick` over a sweep table, shared by `swum pick` (any source) and
// `swum population` (the model of each drawn motor): curve per voltage, then
// pick_operating_point (docs/host.md, "swum pick").
#pragma once

#include <string>
#include <vector>

#include "analysis/operating_point/operating_point.h"
#include "output/sweep_table.h"

namespace swum::host {

/// The rows of `rows` at `amplitude_v` and `load_n` as a curve for the picking rule. Points that were
/// not measured (a device timeout) are holes, not collapses, and are left out.
std::vector<CurveSample> curve_at(const std::vector<SweepRow>& rows, double amplitude_v, double load_n);

/// pick_operating_point on the curve of every (voltage, load), voltage-major in the orders given
/// (the order of swum band's rows). Throws CommandError "<source>: no rows at V V and L N" when
/// a pair has no row.
std::vector<VoltagePick> pick_voltages(const std::vector<SweepRow>& rows, const std::vector<double>& voltages,
                                       const std::vector<double>& loads_n, const PickOptions& options,
                                       const std::string& source);

}  // namespace swum::host
