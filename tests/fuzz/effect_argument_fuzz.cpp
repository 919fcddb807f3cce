// Fuzz target: `swum synth --effect NAME[:key=value,...]` (src/analysis/discrepancy/candidate_effects.h
// apply_effect_argument).
// Invariants: the only error is std::invalid_argument; an accepted argument enables the named
// effect, sets every key=value given (the last one of a key wins), and leaves parameters that pass
// validate_parameters and survive the parameter file: written with format_motor_parameters,
// they parse back to the same values.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "analysis/discrepancy/candidate_effects.h"
#include "formats/csv_cells.h"
#include "fuzz_check.h"
#include "model/parameters.h"
#include "parameter_round_trip.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view argument = swum::fuzz::as_text(data, size);
  swum::MotorParameters parameters;
  try {
    swum::apply_effect_argument(parameters, argument);
  } catch (const std::invalid_argument&) {
    return 0;
  }
  const std::size_t colon = argument.find(':');
  const swum::CandidateEffect* effect = swum::find_candidate_effect(argument.substr(0, colon));
  FUZZ_CHECK(effect != nullptr, "accepted an unknown effect");
  FUZZ_CHECK(swum::effect_enabled(parameters, *effect), "effect %s not enabled", std::string(effect->name).c_str());
  const std::string section = swum::effect_section(*effect);
  for (std::string_view rest = colon == std::string_view::npos ? std::string_view{} : argument.substr(colon + 1);
       !rest.empty();) {
    const std::size_t comma = rest.find(',');
    const std::string_view item = rest.substr(0, comma);
    rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    const std::size_t equals = item.find('=');
    const swum::ParameterSpec* spec = swum::find_parameter_spec(section, item.substr(0, equals));
    FUZZ_CHECK(spec != nullptr && equals != std::string_view::npos, "accepted the item '%s'",
               swum::fuzz::printable(item).c_str());
    double value = 0.0;
    FUZZ_CHECK(swum::parse_number_cell(item.substr(equals + 1), value) == nullptr, "accepted the value of '%s'",
               swum::fuzz::printable(item).c_str());
    // The last assignment of this key is the one in force.
    if (rest.find(std::string(spec->key) + "=") == std::string_view::npos) {
      FUZZ_CHECK(spec->get(parameters) == value, "%s = %.17g given, %.17g set", spec->name().c_str(), value,
                 spec->get(parameters));
    }
  }
  swum::fuzz::check_parameter_file_round_trip(parameters);
  return 0;
}
