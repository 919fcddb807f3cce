// Physical groups of base parameters that the discovery step of the discrepancy workflow
// (discovery.h, docs/discrepancy.md "Discovery") may change when no effect of the library
// explains the residual. The parameters of a group change together in a real motor (both
// modes' damping with temperature, ageing or a batch of ceramic; both modal frequencies with
// the stator's stiffness), so they are fitted as one factor (or one shift): fitted one at a
// time, the partner's change would be absorbed elsewhere. What the library already has is not a group
// here (guide friction, preload with its Hertzian stiffness, the four non-linear constants
// scaled together, droop, heat, wear).
#pragma once

#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/fit/free_parameter.h"
#include "model/parameters.h"

namespace swum {

enum class GroupChange {
  factor,  // every key x the same factor (origin 1)
  shift,   // every key + the same shift in the keys' unit (origin 0)
};

struct ParameterGroup {
  std::string_view name;                 // "stator_damping"
  std::string_view summary;              // one line for reports
  std::array<std::string_view, 2> keys;  // "section.key" of the parameter table; the second may be ""
  GroupChange change = GroupChange::factor;
  double typical = 0.0;  // probe step of the screening (a factor's 1 + typical, a shift's typical)
  double lower = 0.0;    // fit bounds of the factor or the shift (before the parameters' own ranges)
  double upper = 0.0;
};

[[nodiscard]] std::span<const ParameterGroup> parameter_groups();
// nullptr if unknown.
[[nodiscard]] const ParameterGroup* find_parameter_group(std::string_view name);
// "stator_damping, modal_frequencies, ..." (for error messages).
[[nodiscard]] std::string parameter_group_names();

// The group's keys that apply to `baseline` (a factor of a zero value changes nothing, the target
// frequencies are parameters only with geometry = "from_frequencies"); empty: the group does
// not apply.
[[nodiscard]] std::vector<const ParameterSpec*> group_parameters(const ParameterGroup& group,
                                                                 const MotorParameters& baseline);

// Why the group does not apply to `baseline` ("" when it does).
[[nodiscard]] std::string group_not_applicable_reason(const ParameterGroup& group, const MotorParameters& baseline);

// The group as a fit's free parameter around `baseline`: the factor (origin 1) or the shift
// (origin 0), bounded by the group's bounds and by every key's documented range; applying a
// value writes every key from its baseline value. Throws std::invalid_argument when the group
// does not apply to `baseline`.
[[nodiscard]] FreeParameter group_free_parameter(const ParameterGroup& group, const MotorParameters& baseline);

// The library effect a pair of groups is under another name ("" when none): preload_force with
// contact_stiffness is the library's preload (F_P x f, k_e x f^(1/3)); elastic_nonlinearity
// with electroelastic_coupling its electroelastic scale. Such a pair is not searched.
[[nodiscard]] std::string_view library_effect_of_pair(const ParameterGroup& a, const ParameterGroup& b);

}  // namespace swum
