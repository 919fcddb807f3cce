#include "formats/parameter_edit.h"

#include <cmath>
#include <stdexcept>

#include "formats/csv_cells.h"
#include "formats/number_format.h"

namespace swum {
namespace {

std::string_view trim_blanks(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// "--set 'contact.preload_n=x': " - the start of every message about `text`.
std::string prefix(ParameterEditKind kind, std::string_view text) {
  return std::string(parameter_edit_option(kind)) + " '" + printable_cell(text) + "': ";
}

// The keys of one section of the table in its order: "preload_n, stiffness_n_m, ...".
std::string keys_of_section(std::string_view section) {
  std::string names;
  for (const ParameterSpec& spec : parameter_specs()) {
    if (spec.section != section) continue;
    names += names.empty() ? "" : ", ";
    names += std::string(spec.key);
  }
  return names;
}

std::string choices_of(const ParameterSpec& spec) {
  std::string names;
  for (const std::string_view choice : spec.choices) {
    names += names.empty() ? "" : ", ";
    names += quoted(choice);
  }
  return names;
}

// The value text of a --set of a boolean or a choice as a number (0/1, the choice's index);
// false when it names none.
bool named_value(const ParameterSpec& spec, std::string_view text, double& value) {
  if (spec.kind == ParameterKind::boolean) {
    if (text != "true" && text != "false") return false;
    value = text == "true" ? 1.0 : 0.0;
    return true;
  }
  if (text.size() >= 2 && text.front() == '"' && text.back() == '"') text = text.substr(1, text.size() - 2);
  for (std::size_t i = 0; i < spec.choices.size(); ++i) {
    if (spec.choices[i] == text) {
      value = static_cast<double>(i);
      return true;
    }
  }
  return false;
}

}  // namespace

std::string_view parameter_edit_option(ParameterEditKind kind) {
  return kind == ParameterEditKind::set ? "--set" : "--scale";
}

ParameterEdit parse_parameter_edit(ParameterEditKind kind, std::string_view text) {
  const std::size_t equals = text.find('=');
  if (equals == std::string_view::npos) {
    throw std::invalid_argument(prefix(kind, text) + "expected SECTION.KEY=" +
                                (kind == ParameterEditKind::set ? "VALUE" : "FACTOR") + " (no '=')");
  }
  const std::string_view name = trim_blanks(text.substr(0, equals));
  const std::string_view value_text = trim_blanks(text.substr(equals + 1));
  const std::size_t dot = name.rfind('.');
  const std::string_view section = dot == std::string_view::npos ? std::string_view{} : name.substr(0, dot);
  const std::string_view key = dot == std::string_view::npos ? name : name.substr(dot + 1);
  const ParameterSpec* spec = find_parameter_spec(section, key);
  if (spec == nullptr) {
    const std::string keys = keys_of_section(section);
    throw std::invalid_argument(
        prefix(kind, text) + "unknown parameter '" + printable_cell(name) + "' (" +
        (keys.empty() ? "sections: " + parameter_section_names() : "keys of " + std::string(section) + ": " + keys) +
        ")");
  }
  ParameterEdit edit{kind, spec, 0.0, spec->name() + "=" + std::string(value_text)};
  const bool named = spec->kind == ParameterKind::boolean || spec->kind == ParameterKind::choice;
  if (named && kind == ParameterEditKind::scale) {
    throw std::invalid_argument(
        prefix(kind, text) + spec->name() + " is " +
        (spec->kind == ParameterKind::boolean ? "true or false" : "a choice (" + choices_of(*spec) + ")") +
        ", not a number to scale; give it with --set");
  }
  if (named && kind == ParameterEditKind::set) {
    if (!named_value(*spec, value_text, edit.value)) {
      throw std::invalid_argument(
          prefix(kind, text) + spec->name() + " takes " +
          (spec->kind == ParameterKind::boolean ? "true or false" : "one of " + choices_of(*spec)) + ", not '" +
          printable_cell(value_text) + "'");
    }
    return edit;
  }
  if (const char* problem = parse_number_cell(value_text, edit.value); problem != nullptr) {
    throw std::invalid_argument(prefix(kind, text) + "'" + printable_cell(value_text) + "' " + problem);
  }
  return edit;
}

void apply_parameter_edit(MotorParameters& parameters, const ParameterEdit& edit) {
  const ParameterSpec& spec = *edit.spec;
  const double old_value = spec.get(parameters);
  const double value = edit.kind == ParameterEditKind::set ? edit.value : old_value * edit.value;
  std::string problem;
  if (edit.kind == ParameterEditKind::scale && old_value == 0.0 && edit.value != 1.0) {
    // A scaled 0 stays 0: a change the user meant to hide would silently not be there.
    throw std::invalid_argument(prefix(edit.kind, edit.text) + spec.name() +
                                " is 0, so scaling it changes nothing; give a value with --set");
  }
  if (!std::isfinite(value)) {
    problem = "is not finite";
  } else if (value < spec.min_value || value > spec.max_value) {
    problem = "is out of range [" + format_parameter_value(spec, spec.min_value) + ", " +
              format_parameter_value(spec, spec.max_value) + "] " + std::string(spec.unit);
  } else if (spec.kind == ParameterKind::integer && value != std::floor(value)) {
    problem = "is not a whole number";
  }
  if (!problem.empty()) {
    const std::string from = edit.kind == ParameterEditKind::scale
                                 ? " (" + shortest_decimal(old_value) + " x " + shortest_decimal(edit.value) + ")"
                                 : "";
    throw std::invalid_argument(prefix(edit.kind, edit.text) + spec.name() + " = " + format_number(value, "%.10g") +
                                from + " " + problem);
  }
  spec.set(parameters, value);
}

}  // namespace swum
