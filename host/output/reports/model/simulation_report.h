// What `swum simulate` prints and writes: the steady state of one operating point as text or
// as one JSON object (--json), and the CSV trace (--trace).
#pragma once

#include <string>

#include "analysis/steady_state/steady_state.h"

namespace swum::host {

/// The operating point, the steady values and the run's time (pretty JSON, ordered keys, '\n'
/// at the end). `wall_s`: the run's wall time.
std::string simulation_json(const OperatingPoint& point, const SteadyStateResult& r, double wall_s);

/// The same as a few aligned lines of text.
std::string simulation_text(const OperatingPoint& point, const SteadyStateResult& r, double wall_s);

/// The header line of the trace CSV.
std::string simulation_trace_header();

/// Appends one trace row (with '\n') to `csv`.
void append_simulation_trace_row(std::string& csv, const TraceSample& s);

}  // namespace swum::host
