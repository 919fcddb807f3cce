#include "analysis/discrepancy/candidate_effects.h"

#include "formats/csv_cells.h"

#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>

namespace swum {
namespace {

// neutral, typical, bounds and plausible ranges: docs/discrepancy.md explains each choice.
constexpr std::array kEffects{
    CandidateEffect{"electroelastic", "non-linear electroelasticity (c111, c1111, e311, e3111)", "scale", 0.0, 0.5,
                    -2.0, 3.0, 0.4, 1.0, false},
    CandidateEffect{"thermal", "stator temperature rise from the modal damping power", "thermal_resistance_k_per_w",
                    0.0, 3.0, 0.0, 40.0, 3.0, 8.0, true},
    CandidateEffect{"wear", "friction coefficient change with sliding distance", "friction_change", 0.0, -0.2, -0.8,
                    2.0, 0.25, 0.45, true},
    CandidateEffect{"preload", "preload / contact stiffness error (Hertzian k_e ~ F_P^(1/3))", "preload_factor", 1.0,
                    -0.15, 0.3, 2.5, 0.7, 0.85, false},
    CandidateEffect{"guide_friction", "extra linear-guide friction (dead-zone width)", "extra_coefficient", 0.0, 0.02,
                    -0.04, 0.5, 0.02, 0.06, false},
    CandidateEffect{"amplifier_droop", "drive droop through the amplifier source resistance", "source_resistance_ohm",
                    0.0, 40.0, 0.0, 2000.0, 60.0, 150.0, false},
};

const ParameterSpec& spec_of(const CandidateEffect& effect, std::string_view key) {
  const std::string section = effect_section(effect);
  const ParameterSpec* spec = find_parameter_spec(section, key);
  if (spec == nullptr) {
    throw std::logic_error("parameter table has no " + section + "." + std::string(key));
  }
  return *spec;
}

}  // namespace

std::span<const CandidateEffect> candidate_effects() { return kEffects; }

const CandidateEffect* find_candidate_effect(std::string_view name) {
  for (const auto& e : kEffects) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

std::string candidate_effect_names() {
  std::string names;
  for (const auto& e : kEffects) {
    if (!names.empty()) names += ", ";
    names += std::string(e.name);
  }
  return names;
}

std::string effect_section(const CandidateEffect& effect) { return "effects." + std::string(effect.name); }

const ParameterSpec& effect_free_spec(const CandidateEffect& effect) { return spec_of(effect, effect.free_key); }

bool effect_enabled(const MotorParameters& p, const CandidateEffect& effect) {
  return spec_of(effect, "enabled").get(p) != 0.0;
}

void enable_effect(MotorParameters& p, const CandidateEffect& effect, double value) {
  spec_of(effect, "enabled").set(p, 1.0);
  effect_free_spec(effect).set(p, value);
}

double effect_value(const MotorParameters& p, const CandidateEffect& effect) { return effect_free_spec(effect).get(p); }

void apply_effect_argument(MotorParameters& p, std::string_view argument) {
  const std::size_t colon = argument.find(':');
  const std::string_view name = argument.substr(0, colon);
  const CandidateEffect* effect = find_candidate_effect(name);
  if (effect == nullptr) {
    throw std::invalid_argument("unknown effect '" + std::string(name) + "' (known: " + candidate_effect_names() + ")");
  }
  const std::string section = effect_section(*effect);
  std::string keys;
  for (const auto& spec : parameter_specs()) {
    if (spec.section != section || spec.key == "enabled") continue;
    keys += keys.empty() ? "" : ", ";
    keys += std::string(spec.key);
  }
  spec_of(*effect, "enabled").set(p, 1.0);
  if (colon == std::string_view::npos) return;
  std::string_view rest = argument.substr(colon + 1);
  if (rest.empty()) {
    throw std::invalid_argument("effect '" + std::string(name) + "': expected key=value after ':' (keys: " + keys +
                                ")");
  }
  for (bool more = true; more;) {
    const std::size_t comma = rest.find(',');
    const std::string_view item = rest.substr(0, comma);
    more = comma != std::string_view::npos;  // "k=v," ends in an empty item: an error below
    rest = more ? rest.substr(comma + 1) : std::string_view{};
    const std::size_t equals = item.find('=');
    const std::string_view key = item.substr(0, equals);
    const ParameterSpec* spec = find_parameter_spec(section, key);
    if (equals == std::string_view::npos || spec == nullptr || key == "enabled") {
      throw std::invalid_argument("effect '" + std::string(name) + "': '" + std::string(item) +
                                  "' is not key=value with a key of " + section + " (keys: " + keys + ")");
    }
    const std::string_view text = item.substr(equals + 1);
    double value = 0.0;
    if (parse_number_cell(text, value) != nullptr) {
      throw std::invalid_argument("effect '" + std::string(name) + "': " + std::string(key) + " = '" +
                                  std::string(text) + "' is not a finite number");
    }
    if (value < spec->min_value || value > spec->max_value) {
      throw std::invalid_argument("effect '" + std::string(name) + "': " + std::string(key) + " = " +
                                  std::string(text) + " is out of range [" +
                                  format_parameter_value(*spec, spec->min_value) + ", " +
                                  format_parameter_value(*spec, spec->max_value) + "] " + std::string(spec->unit));
    }
    spec->set(p, value);
  }
}

FreeParameter effect_free_parameter(const CandidateEffect& effect) {
  const ParameterSpec& spec = effect_free_spec(effect);
  return {spec.name(),
          std::string(spec.unit),
          effect.neutral,
          effect.typical,
          effect.lower,
          effect.upper,
          [&effect](MotorParameters& p, double value) { enable_effect(p, effect, value); }};
}

}  // namespace swum
