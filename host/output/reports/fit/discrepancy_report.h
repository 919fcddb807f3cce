// What `swum discrepancy` prints and writes (docs/discrepancy.md): the JSON summary (--json and
// summary.json), the text summary, report.md with its plots, and the comment header of
// augmented.toml.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "analysis/discrepancy/discrepancy.h"

namespace swum::host {

/// The result as one JSON document (pretty, ordered keys, '\n' at the end).
std::string discrepancy_json(const DiscrepancyResult& r, double wall_s);

/// The terminal summary: baseline, each round's candidates, the named effects with their
/// evidence, the held-out gap per quantity and the conclusion.
std::string discrepancy_summary_text(const DiscrepancyResult& r);

/// Per measured quantity, measured, baseline and augmented values against the point index in
/// session order, one PNG each in `dir`; returns the file names written, in order.
std::vector<std::string> write_discrepancy_plots(const std::filesystem::path& dir, const MeasurementSet& set,
                                                 const DiscrepancyResult& r);

/// report.md. `command_line`: the options after `swum discrepancy` that name the inputs;
/// `plots`: the file names write_discrepancy_plots returned.
std::string discrepancy_report_markdown(const std::string& command_line, const MeasurementSet& set,
                                        const DiscrepancyResult& r, const std::vector<std::string>& plots);

/// The comment lines at the top of augmented.toml (each "# ...\n"): one per named effect.
std::string discrepancy_augmented_header(const std::string& command_line, const DiscrepancyResult& r);

}  // namespace swum::host
