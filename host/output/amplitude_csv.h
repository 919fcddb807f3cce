// Measured free-stator amplitudes (the input of `swum identify`): CSV with the columns
// amplitude_v,frequency_hz,tip_normal_um,tip_tangential_um (any order, extra columns ignored, either
// amplitude cell may be empty, '#' comment lines and blank lines skipped).
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/free_stator/amplitude_measurement.h"

namespace swum::host {

/// Parses the text of `source_name`. Throws CommandError "FILE:LINE:COLUMN: ..." for a
/// missing column, a wrong cell count, a non-numeric or non-finite cell, a negative voltage or
/// amplitude, a non-positive frequency, a row without any amplitude, and for fewer than
/// `min_amplitudes` amplitude values in total (one per fitted parameter).
std::vector<AmplitudeMeasurement> parse_amplitude_csv(std::string_view text, std::string_view source_name,
                                                      int min_amplitudes = 4);

/// The same layout, for writing data (empty cells for missing amplitudes).
std::string format_amplitude_csv(std::span<const AmplitudeMeasurement> data);

}  // namespace swum::host
