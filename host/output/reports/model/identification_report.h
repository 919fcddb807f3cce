// What `swum identify` prints and writes (paper Sec. 4, model_spec §6.5): the JSON summary
// (--json and summary.json), the text table (stdout and summary.txt), the comment header of
// the fitted parameter file, and the report's residuals.csv and fit plots.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "analysis/identification/identification.h"
#include "model/motor_model.h"

namespace swum::host {

/// The result as one JSON document (pretty, ordered keys, '\n' at the end).
std::string identification_json(const IdentificationResult& r);

/// One line per constant (value, standard error, status) and the RMS residual.
std::string identification_summary_text(const IdentificationResult& r);

/// The comment lines at the top of the fitted parameter file, a blank line after them.
/// `command_line`: the options after `swum identify` that name the inputs.
std::string identification_fitted_header(const std::string& command_line, const IdentificationResult& r);

/// amplitude_v,frequency_hz and per axis the measured and the fitted amplitude, one row per point.
std::string identification_residuals_csv(const IdentificationResult& r);

/// Data against fitted curves, fit_normal.png and fit_tangential.png in `dir` (paper Figs.
/// 7-8): per frequency, the fitted amplitude along a voltage up-sweep and the measured points.
void write_identification_plots(const std::filesystem::path& dir, const MotorModel& fitted_model,
                                const std::vector<AmplitudeMeasurement>& data);

}  // namespace swum::host
