// Fuzz target: a motor parameter file (TOML; src/formats/parameter_file.h parse_motor_parameters),
// the --config of every `swum` command and of swum-emu.
// Invariants: the only error is ParameterError (a toml++ exception or any other escaping is a
// crash); accepted parameters pass validate_parameters, and format_motor_parameters writes
// them as a file that parses back to the same value of every parameter of the table.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "formats/parameter_file.h"
#include "fuzz_check.h"
#include "parameter_round_trip.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  swum::MotorParameters parameters;
  try {
    parameters = swum::parse_motor_parameters(swum::fuzz::as_text(data, size), "fuzz.toml");
  } catch (const swum::ParameterError&) {
    return 0;
  }
  swum::fuzz::check_parameter_file_round_trip(parameters);
  return 0;
}
