// Number formats the per-command reports share: relative values as percent, and JSON numbers
// that are null where a value is unknown or not finite.
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "formats/number_format.h"

namespace swum::host {

/// 0.0123 -> "1.23 %" (three significant digits).
inline std::string percent(double v) { return format_number(100.0 * v, "%.3g") + " %"; }

/// A drive level as a plot legend or a heading: 100 -> "100 V" (a terminal amplitude).
inline std::string amplitude_v_label(double amplitude_v) { return format_number(amplitude_v, "%g") + " V"; }

/// The value as a JSON number; null when it is NaN or infinite.
inline nlohmann::ordered_json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
}

/// The value as a JSON number when it is known and finite; null otherwise.
inline nlohmann::ordered_json number_or_null(bool known, double v) {
  return known ? finite_or_null(v) : nlohmann::ordered_json(nullptr);
}

}  // namespace swum::host
