// The spreads file of `swum population` (docs/population.md): which parameters of the
// parameter file vary from motor to motor (manufacturing tolerances) and how, around the
// nominal motor of --config. TOML text in, no file I/O; validated once here, so every draw
// lies inside the parameter's documented range.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "model/parameters.h"

namespace swum {

enum class SpreadDistribution {
  normal,   // nominal + sigma z, z standard normal, redrawn while |z| > truncate
  uniform,  // uniform on [low, high]
};

struct ParameterSpread {
  const ParameterSpec* spec = nullptr;  // the parameter (spec->name() = "section.key")
  SpreadDistribution distribution = SpreadDistribution::normal;
  double nominal = 0.0;      // its value in the nominal parameter set
  double sigma = 0.0;        // normal: standard deviation in the parameter's unit (>= 0)
  double truncate = 3.0;     // normal: draws are kept within nominal -/+ truncate sigma
  double low = 0.0;          // every value a draw can take lies in [low, high] ...
  double high = 0.0;         // ... and [low, high] lies in the spec's documented range
  std::uint64_t stream = 0;  // the parameter's own random stream: a hash of its name
  int line = 0;              // where the file declares it (for messages)
};

// Parses a spreads file against the nominal parameters (percent forms are of the nominal
// value). Each entry is a table under the parameter's section, e.g.
//   [contact]
//   preload_n = { distribution = "normal", sigma_percent = 5, truncate = 3 }
//   friction_coefficient = { distribution = "uniform", min = 0.3, max = 0.4 }
// Returns the spreads in parameter-table order. Throws ParameterError "SOURCE:LINE: what"
// for a TOML error, an unknown section or parameter, a parameter that is not a real number of
// [stator], [contact] or [mover] or is unused by the nominal geometry mode, an unknown
// distribution or key, a missing or doubled width, a negative sigma or width, min > max, a
// truncation outside 0.5..10 sigma, a percentage of a nominal 0, or a draw range outside the
// parameter's documented range. An empty file is valid: no parameter varies.
[[nodiscard]] std::vector<ParameterSpread> parse_parameter_spreads(std::string_view toml_text,
                                                                   std::string_view source_name,
                                                                   const MotorParameters& nominal);

}  // namespace swum
