#include "formats/parameter_file.h"

#include <cmath>
#include <optional>
#include <string>

#include <toml++/toml.h>

#include "formats/csv_cells.h"
#include "formats/number_format.h"
#include "formats/toml_number.h"

namespace swum {
namespace {

std::string where(std::string_view source_name, const toml::source_region& region) {
  std::string s(source_name);
  if (region.begin.line > 0) s += ":" + std::to_string(region.begin.line);
  return s;
}

std::string allowed_text(const ParameterSpec& spec) {
  if (spec.kind == ParameterKind::choice) {
    std::string s = "one of";
    for (auto c : spec.choices) s.append(" ").append(quoted(c));
    return s;
  }
  if (spec.kind == ParameterKind::boolean) return "true or false";
  return std::string("[") + format_parameter_value(spec, spec.min_value) + ", " +
         format_parameter_value(spec, spec.max_value) + "] " + std::string(spec.unit);
}

[[noreturn]] void fail(std::string_view source_name, const toml::source_region& region, const ParameterSpec& spec,
                       const std::string& problem) {
  throw ParameterError(where(source_name, region) + ": " + std::string(spec.section) + "." + std::string(spec.key) +
                       " " + problem + " (allowed: " + allowed_text(spec) + ")");
}

double read_value(const toml::node& node, const ParameterSpec& spec, std::string_view source_name) {
  const auto& region = node.source();
  const auto in_range = [&](double v) {
    if (v < spec.min_value || v > spec.max_value) {
      fail(source_name, region, spec, "value " + format_parameter_value(spec, v) + " is out of range");
    }
    return v;
  };
  switch (spec.kind) {
    case ParameterKind::real: {
      const std::optional<double> number = toml_number(node);
      if (!number) fail(source_name, region, spec, "must be a number");
      const double v = *number;
      if (!std::isfinite(v)) fail(source_name, region, spec, "must be finite (NaN/Inf given)");
      return in_range(v);
    }
    case ParameterKind::integer: {
      auto i = node.as_integer();
      if (!i) fail(source_name, region, spec, "must be an integer");
      return in_range(static_cast<double>(i->get()));
    }
    case ParameterKind::boolean: {
      auto b = node.as_boolean();
      if (!b) fail(source_name, region, spec, "must be a boolean");
      return b->get() ? 1.0 : 0.0;
    }
    case ParameterKind::choice: {
      auto s = node.as_string();
      if (!s) fail(source_name, region, spec, "must be a string");
      for (std::size_t k = 0; k < spec.choices.size(); ++k) {
        if (spec.choices[k] == s->get()) return static_cast<double>(k);
      }
      fail(source_name, region, spec, std::string("has unknown value ").append(quoted(s->get())));
    }
  }
  return 0.0;
}

}  // namespace

MotorParameters parse_motor_parameters(std::string_view toml_text, std::string_view source_name) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    throw ParameterError(where(source_name, e.source()) + ": TOML syntax error: " + printable_cell(e.description()));
  }
  MotorParameters parameters{};
  const auto known_section = [](std::string_view name) {
    for (const auto& spec : parameter_specs()) {
      if (spec.section == name) return true;
    }
    return false;
  };
  // A table of sub-sections ("effects" holds "effects.thermal", ...).
  const auto known_parent = [](std::string_view name) {
    for (const auto& spec : parameter_specs()) {
      if (spec.section.size() > name.size() && spec.section.starts_with(name) && spec.section[name.size()] == '.') {
        return true;
      }
    }
    return false;
  };
  // The droop effect's own C0 of files written before it read the stator's (docs/parameters.md,
  // "One C0"): read, and it must repeat stator.clamped_capacitance_nf.
  std::optional<double> legacy_droop_c0;
  std::string legacy_droop_c0_where;
  const auto read_section = [&](const std::string& section, const toml::node& section_node) {
    const auto* table = section_node.as_table();
    if (table == nullptr) {
      throw ParameterError(where(source_name, section_node.source()) + ": " + section + " must be a table ([" +
                           section + "])");
    }
    for (auto&& [key, node] : *table) {
      if (section == "effects.amplifier_droop" && key.str() == "clamped_capacitance_nf") {
        ParameterSpec legacy = *find_parameter_spec("stator", "clamped_capacitance_nf");  // its unit and range
        legacy.section = section;
        legacy_droop_c0 = read_value(node, legacy, source_name);
        legacy_droop_c0_where = where(source_name, node.source());
        continue;
      }
      if (section == "options" && key.str() == "voltage_convention") {
        throw ParameterError(where(source_name, node.source()) +
                             ": options.voltage_convention is retired (inputs are terminal amplitudes, V); "
                             "say how the paper's voltages read with options.paper_voltage_axis");
      }
      const auto* spec = find_parameter_spec(section, key.str());
      if (spec == nullptr) {
        throw ParameterError(where(source_name, node.source()) + ": unknown key " + section + "." +
                             printable_cell(key.str()) + " (see docs/parameters.md for the valid keys)");
      }
      spec->set(parameters, read_value(node, *spec, source_name));
    }
  };
  for (auto&& [section_key, section_node] : root) {
    const std::string section(section_key.str());
    if (known_section(section)) {
      read_section(section, section_node);
      continue;
    }
    const auto* parent = section_node.as_table();
    if (!known_parent(section) || parent == nullptr) {
      throw ParameterError(where(source_name, section_node.source()) + ": unknown section [" + section +
                           "] (known: " + parameter_section_names() + ")");
    }
    for (auto&& [sub_key, sub_node] : *parent) {
      const std::string sub_section = section + "." + std::string(sub_key.str());
      if (!known_section(sub_section)) {
        throw ParameterError(where(source_name, sub_node.source()) + ": unknown section [" + sub_section +
                             "] (known: " + parameter_section_names() + ")");
      }
      read_section(sub_section, sub_node);
    }
  }
  if (legacy_droop_c0 && *legacy_droop_c0 != parameters.stator.clamped_capacitance_nf) {
    throw ParameterError(legacy_droop_c0_where + ": effects.amplifier_droop.clamped_capacitance_nf = " +
                         format_number(*legacy_droop_c0) + " differs from stator.clamped_capacitance_nf = " +
                         format_number(parameters.stator.clamped_capacitance_nf) +
                         ": the droop effect uses the stator's C0; set only [stator] clamped_capacitance_nf");
  }
  validate_parameters(parameters, source_name);
  return parameters;
}

std::string format_motor_parameters(const MotorParameters& parameters) {
  std::string out;
  std::string_view section;
  for (const auto& spec : parameter_specs()) {
    if (spec.section != section) {
      if (!section.empty()) out += "\n";
      section = spec.section;
      out += std::string("[") + std::string(section) + "]\n";
    }
    out += std::string(spec.key) + " = " + format_parameter_value(spec, spec.get(parameters)) + "\n";
  }
  return out;
}

}  // namespace swum
