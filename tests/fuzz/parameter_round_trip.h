// Shared by the parameter-file and --effect targets: parameters the program accepted are valid and
// survive the parameter file (format_motor_parameters, then parse_motor_parameters: every
// parameter of the table reads back to the same value, and writes back to the same text).
#pragma once

#include <string>

#include "formats/parameter_file.h"
#include "fuzz_check.h"
#include "model/parameters.h"

namespace swum::fuzz {

inline void check_parameter_file_round_trip(const MotorParameters& parameters) {
  try {
    validate_parameters(parameters, "accepted");
  } catch (const ParameterError& e) {
    FUZZ_CHECK(false, "accepted parameters fail validation: %s", e.what());
  }
  const std::string written = format_motor_parameters(parameters);
  MotorParameters again;
  try {
    again = parse_motor_parameters(written, "written.toml");
  } catch (const ParameterError& e) {
    FUZZ_CHECK(false, "the written parameters are refused: %s", e.what());
  }
  for (const ParameterSpec& spec : parameter_specs()) {
    FUZZ_CHECK(spec.get(parameters) == spec.get(again), "%s: %.17g written, %.17g read back", spec.name().c_str(),
               spec.get(parameters), spec.get(again));
  }
  FUZZ_CHECK(format_motor_parameters(again) == written, "writing the read-back parameters differs");
}

}  // namespace swum::fuzz
