// TOML text -> MotorParameters (validated once here). No file I/O: the caller reads the file
// and passes its text and name.
#pragma once

#include <string>
#include <string_view>

#include "model/parameters.h"

namespace swum {

// Parses a parameter file. Sections and keys are those of parameter_specs(); keys that are
// absent keep their MotorParameters{} default. Throws ParameterError (message: source name,
// line, section.key, the problem and the allowed range) on syntax errors, unknown sections
// or keys, wrong types, NaN/Inf and out-of-range values.
[[nodiscard]] MotorParameters parse_motor_parameters(std::string_view toml_text, std::string_view source_name);

// The inverse: a complete TOML document with every parameter (round-trips through
// parse_motor_parameters).
[[nodiscard]] std::string format_motor_parameters(const MotorParameters& parameters);

}  // namespace swum
