#include "analysis/discrepancy/parameter_groups.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "formats/number_format.h"

namespace swum {
namespace {

// Typical steps and bounds: docs/discrepancy.md ("Discovery") says why. Factors may go from a
// tenth to ten times the config's value (the discovery is not a calibration: it has no prior
// spread to hold a change to); shifts of the natural frequencies up to 3 kHz.
constexpr std::array kGroups{
    ParameterGroup{"stator_damping",
                   "modal damping of both stator modes, C1 and C2 (temperature, ageing, a batch of ceramic)",
                   {"stator.damping_l1_n_s_m", "stator.damping_b2_n_s_m"},
                   GroupChange::factor,
                   0.25,
                   0.1,
                   10.0},
    ParameterGroup{"modal_frequencies",
                   "natural frequencies of both stator modes, L1 and B2 (stiffness or mass of the stator as made)",
                   {"stator.target_l1_frequency_hz", "stator.target_b2_frequency_hz"},
                   GroupChange::shift,
                   100.0,
                   -3000.0,
                   3000.0},
    ParameterGroup{"contact_stiffness",
                   "normal stiffness of the contact layer, k_e (its modulus; the stiffened resonance)",
                   {"contact.stiffness_n_m", ""},
                   GroupChange::factor,
                   0.3,
                   0.1,
                   10.0},
    ParameterGroup{"tip_compliance",
                   "tangential stiffness of the tip, k_t (Jenkins contact: where stick gives way to slip)",
                   {"contact.tangential_stiffness_n_m", ""},
                   GroupChange::factor,
                   0.3,
                   0.1,
                   10.0},
    ParameterGroup{"preload_force",
                   "preload force F_P alone (a spring set at assembly; the library's preload also moves k_e)",
                   {"contact.preload_n", ""},
                   GroupChange::factor,
                   0.1,
                   0.1,
                   10.0},
    ParameterGroup{"contact_friction",
                   "friction coefficient of the tip on the mover, mu_c (a constant change: no time needed)",
                   {"contact.friction_coefficient", ""},
                   GroupChange::factor,
                   0.15,
                   0.1,
                   10.0},
    ParameterGroup{"mover_mass",
                   "mover mass (the steady states see it through the guide's normal force, mu_s m g)",
                   {"mover.mass_kg", ""},
                   GroupChange::factor,
                   0.5,
                   0.1,
                   10.0},
    ParameterGroup{"mover_damping",
                   "viscous damping of the mover, c (speed level, growing with speed)",
                   {"mover.damping_n_s_m", ""},
                   GroupChange::factor,
                   0.3,
                   0.1,
                   10.0},
    ParameterGroup{"elastic_nonlinearity",
                   "non-linear elastic constants c111 and c1111 (amplitude softening of L1)",
                   {"stator.c111_pa", "stator.c1111_pa"},
                   GroupChange::factor,
                   0.3,
                   0.1,
                   10.0},
    ParameterGroup{"electroelastic_coupling",
                   "non-linear electroelastic constants e311 and e3111 (voltage-dependent stiffness)",
                   {"stator.e311_c_per_v_m", "stator.e3111_c_per_v_m"},
                   GroupChange::factor,
                   0.3,
                   0.1,
                   10.0},
};

const ParameterSpec& spec_named(std::string_view name) {
  const std::size_t dot = name.find('.');
  const ParameterSpec* spec = find_parameter_spec(name.substr(0, dot), name.substr(dot + 1));
  if (spec == nullptr) throw std::logic_error("parameter table has no " + std::string(name));
  return *spec;
}

}  // namespace

std::span<const ParameterGroup> parameter_groups() { return kGroups; }

const ParameterGroup* find_parameter_group(std::string_view name) {
  for (const ParameterGroup& g : kGroups) {
    if (g.name == name) return &g;
  }
  return nullptr;
}

std::string parameter_group_names() {
  std::string out;
  for (const ParameterGroup& g : kGroups) out += (out.empty() ? "" : ", ") + std::string(g.name);
  return out;
}

std::vector<const ParameterSpec*> group_parameters(const ParameterGroup& group, const MotorParameters& baseline) {
  std::vector<const ParameterSpec*> out;
  for (std::string_view key : group.keys) {
    if (key.empty()) continue;
    if (key.starts_with("stator.target_") && baseline.stator.geometry != GeometryMode::from_frequencies) continue;
    const ParameterSpec& spec = spec_named(key);
    if (group.change == GroupChange::factor && spec.get(baseline) == 0.0) continue;
    out.push_back(&spec);
  }
  return out;
}

std::string group_not_applicable_reason(const ParameterGroup& group, const MotorParameters& baseline) {
  if (!group_parameters(group, baseline).empty()) return "";
  return group.change == GroupChange::shift
             ? "the natural frequencies are parameters only with stator.geometry = \"from_frequencies\""
             : "its parameters are 0 in this config";
}

FreeParameter group_free_parameter(const ParameterGroup& group, const MotorParameters& baseline) {
  const std::vector<const ParameterSpec*> specs = group_parameters(group, baseline);
  if (specs.empty()) {
    throw std::invalid_argument("group " + std::string(group.name) + " does not apply to this config (" +
                                group_not_applicable_reason(group, baseline) + ")");
  }
  double lower = group.lower;
  double upper = group.upper;
  std::vector<double> base;
  for (const ParameterSpec* s : specs) {
    const double v = s->get(baseline);
    base.push_back(v);
    if (group.change == GroupChange::shift) {
      lower = std::max(lower, s->min_value - v);
      upper = std::min(upper, s->max_value - v);
    } else if (v > 0.0) {
      lower = std::max(lower, s->min_value / v);
      upper = std::min(upper, s->max_value / v);
    } else {
      lower = std::max(lower, s->max_value / v);
      upper = std::min(upper, s->min_value / v);
    }
  }
  const bool shift = group.change == GroupChange::shift;
  return {std::string(group.name),
          shift ? std::string(specs.front()->unit) : std::string("factor"),
          shift ? 0.0 : 1.0,
          group.typical,
          lower,
          upper,
          [specs, base, shift](MotorParameters& p, double value) {
            for (std::size_t k = 0; k < specs.size(); ++k) specs[k]->set(p, shift ? base[k] + value : base[k] * value);
          }};
}

std::string_view library_effect_of_pair(const ParameterGroup& a, const ParameterGroup& b) {
  constexpr std::array<std::array<std::string_view, 3>, 2> kPairs{{
      {"preload_force", "contact_stiffness", "preload"},
      {"elastic_nonlinearity", "electroelastic_coupling", "electroelastic"},
  }};
  for (const auto& pair : kPairs) {
    if ((a.name == pair[0] && b.name == pair[1]) || (a.name == pair[1] && b.name == pair[0])) return pair[2];
  }
  return "";
}

}  // namespace swum
