// What `swum calibrate` prints and writes (docs/calibration.md): the JSON summary (--json and
// summary.json), the text summary, the markdown report, its plots and the comment header of
// the fitted parameter file.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "analysis/calibration/calibration.h"

namespace swum::host {

/// The result as one JSON document (pretty, ordered keys, '\n' at the end). `measured`: the
/// fit used a measured sweep (adds "measurements").
std::string calibration_json(const CalibrationResult& r, bool measured, double wall_s);

/// The terminal summary: free set, parameters, RMS (when measured), facts, pushes, fronts and
/// the conclusion, one '\n'-terminated line each.
std::string calibration_summary_text(const CalibrationResult& r, bool measured);

/// Measured against prior and fitted values over frequency, one PNG per quantity and load in
/// `dir`; returns the file names written, in order.
std::vector<std::string> write_calibration_plots(const std::filesystem::path& dir, const MeasurementSet& set,
                                                 const CalibrationResult& r);

/// report.md. `command_line`: the options after `swum calibrate`; `set`: the measured sweep or
/// null; `plots`: the file names write_calibration_plots returned.
std::string calibration_report_markdown(const std::string& command_line, const MeasurementSet* set,
                                        const CalibrationResult& r, const std::vector<std::string>& plots,
                                        double wall_s);

/// The comment lines at the top of the fitted parameter file (each "# ...\n").
std::string calibration_fitted_header(const std::string& command_line, const CalibrationResult& r);

}  // namespace swum::host
