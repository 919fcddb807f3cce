// The library of candidate effects of the discrepancy workflow (docs/discrepancy.md): for each
// `[effects.<name>]` table of the parameter table, its free parameter, the value at which the
// effect vanishes, a typical magnitude, fit bounds and the documented plausible range.
// Parameters are reached through the parameter table (parameters.h), never by ad-hoc keys.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "analysis/fit/free_parameter.h"
#include "model/parameters.h"

namespace swum {

struct CandidateEffect {
  std::string_view name;      // "thermal"; the section is "effects." + name
  std::string_view summary;   // one line for reports
  std::string_view free_key;  // the fitted key of the section
  double neutral = 0.0;       // free value at which the effect vanishes (= baseline model)
  double typical = 0.0;       // typical signed magnitude (probe step of the screening)
  double lower = 0.0;         // fit bounds
  double upper = 0.0;
  double plausible_low = 0.0;  // documented plausible range of real motors (tests draw here)
  double plausible_high = 0.0;
  bool needs_time = false;  // builds up over the session: needs time_s
};

[[nodiscard]] std::span<const CandidateEffect> candidate_effects();
// nullptr if unknown.
[[nodiscard]] const CandidateEffect* find_candidate_effect(std::string_view name);
// "electroelastic, thermal, ..." (for error messages).
[[nodiscard]] std::string candidate_effect_names();

[[nodiscard]] std::string effect_section(const CandidateEffect& effect);
[[nodiscard]] const ParameterSpec& effect_free_spec(const CandidateEffect& effect);

[[nodiscard]] bool effect_enabled(const MotorParameters& p, const CandidateEffect& effect);
// Enables the effect with the free parameter at `value` (other keys unchanged).
void enable_effect(MotorParameters& p, const CandidateEffect& effect, double value);
[[nodiscard]] double effect_value(const MotorParameters& p, const CandidateEffect& effect);

// The effect's free parameter for a fit: origin = neutral, scale = typical, its fit bounds;
// applying a value enables the effect.
[[nodiscard]] FreeParameter effect_free_parameter(const CandidateEffect& effect);

// Applies "NAME" (default magnitudes of EffectParameters{}) or "NAME:key=value,key=value" to
// `p` and enables the effect. Throws std::invalid_argument naming the unknown effect (with
// the known names), the unknown key (with the keys of that effect), or the bad value.
void apply_effect_argument(MotorParameters& p, std::string_view argument);

}  // namespace swum
