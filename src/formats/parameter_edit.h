// One change of one parameter of the table on a command line, "SECTION.KEY=VALUE" (`swum synth
// --set` and `--scale`, docs/discrepancy.md): the one parser of such items and the one place that
// applies them, so that any base parameter can be moved the way a config file would move it.
//
// The key is the table's "section.key" (effects.thermal.time_constant_s: the section is what lies
// before the last dot). Blanks around the key and the value are dropped, as in comma lists.
// VALUE is a finite number; for --set of a boolean also true/false, of a choice one of its names
// (with or without double quotes), as a TOML file writes them. --scale multiplies the value the
// parameters hold by VALUE and refuses booleans and choices.
#pragma once

#include <string>
#include <string_view>

#include "model/parameters.h"

namespace swum {

enum class ParameterEditKind {
  set,    // write VALUE
  scale,  // multiply the current value by VALUE
};

struct ParameterEdit {
  ParameterEditKind kind = ParameterEditKind::set;
  const ParameterSpec* spec = nullptr;
  double value = 0.0;  // set: the value (boolean 0/1, choice index); scale: the factor
  std::string text;    // "section.key=VALUE" as read, blanks around key and value dropped
};

// "--set" or "--scale": the option the kind is given with, the prefix of every message.
[[nodiscard]] std::string_view parameter_edit_option(ParameterEditKind kind);

// Parses `text`. Throws std::invalid_argument, one line naming the option and the text: no '=',
// an unknown section or key (with the keys of the section, or the sections), a value that is not
// a finite number (nor a name the parameter takes), a factor on a boolean or a choice.
[[nodiscard]] ParameterEdit parse_parameter_edit(ParameterEditKind kind, std::string_view text);

// Applies `edit` to `parameters`. Throws std::invalid_argument, naming the option, the text and
// the key, when the resulting value is outside the parameter's range (or not finite, or not a
// whole number for an integer key, a scale of a 0); `parameters` is then unchanged.
void apply_parameter_edit(MotorParameters& parameters, const ParameterEdit& edit);

}  // namespace swum
