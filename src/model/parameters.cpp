#include "model/parameters.h"

#include "model/machine/output_network.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <type_traits>

namespace swum {
namespace {

// Accessors generated from pointers to members: section of MotorParameters, then field.
template <auto Section, auto Member>
double get_field(const MotorParameters& p) {
  const auto& value = (p.*Section).*Member;
  using T = std::remove_cvref_t<decltype(value)>;
  if constexpr (std::is_enum_v<T>) {
    return static_cast<double>(static_cast<int>(value));
  } else {
    return static_cast<double>(value);
  }
}

template <auto Section, auto Member>
void set_field(MotorParameters& p, double v) {
  auto& value = (p.*Section).*Member;
  using T = std::remove_cvref_t<decltype(value)>;
  if constexpr (std::is_enum_v<T>) {
    value = static_cast<T>(static_cast<int>(v));
  } else if constexpr (std::is_same_v<T, bool>) {
    value = v != 0.0;
  } else {
    value = static_cast<T>(v);
  }
}

// Effect parameters live one level deeper: MotorParameters::effects.<effect>.<member>.
template <auto Effect, auto Member>
double get_effect_field(const MotorParameters& p) {
  return static_cast<double>((p.effects.*Effect).*Member);
}

template <auto Effect, auto Member>
void set_effect_field(MotorParameters& p, double v) {
  auto& value = (p.effects.*Effect).*Member;
  using T = std::remove_cvref_t<decltype(value)>;
  if constexpr (std::is_same_v<T, bool>) {
    value = v != 0.0;
  } else {
    value = static_cast<T>(v);
  }
}

constexpr std::array<std::string_view, 2> kGeometryChoices{"from_frequencies", "explicit"};
constexpr std::array<std::string_view, 2> kPaperAxisChoices{"peak_to_peak", "amplitude"};
constexpr std::array<std::string_view, 2> kLeverChoices{"same_as_force", "free_tip"};
constexpr std::array<std::string_view, 2> kPrefactorChoices{"derived", "paper_x4"};
constexpr std::array<std::string_view, 2> kDiagonalChoices{"standard", "swapped"};
constexpr std::array<std::string_view, 2> kFrictionChoices{"coulomb_projection", "erf_newton"};
constexpr std::array<std::string_view, 2> kStepKernelChoices{"fused", "generic"};
constexpr std::array<std::string_view, 2> kPreloadChoices{"both_ends", "back_end_constant"};
constexpr std::array<std::string_view, 2> kGuideChoices{"smoothed_sign", "implicit_coulomb"};

constexpr std::span<const std::string_view> kNone{};

#define SWUM_REAL(SEC, STRUCT, KEY, UNIT, MIN, MAX, DESC)                                                            \
  ParameterSpec {                                                                                                    \
#SEC, #KEY, UNIT, DESC, ParameterKind::real, MIN, MAX, kNone, &get_field < &MotorParameters::SEC, &STRUCT::KEY>, \
        &set_field < &MotorParameters::SEC, &STRUCT::KEY>                                                            \
  }
#define SWUM_INT(SEC, STRUCT, KEY, UNIT, MIN, MAX, DESC)                                                 \
  ParameterSpec {                                                                                        \
#SEC, #KEY, UNIT, DESC, ParameterKind::integer, MIN, MAX, kNone, &get_field < &MotorParameters::SEC, \
        &STRUCT::KEY>, &set_field < &MotorParameters::SEC, &STRUCT::KEY>                                 \
  }
#define SWUM_CHOICE(SEC, STRUCT, KEY, CHOICES, DESC)                                                         \
  ParameterSpec {                                                                                            \
#SEC, #KEY, "-", DESC, ParameterKind::choice, 0.0, static_cast < double>(CHOICES.size() - 1), CHOICES,   \
        &get_field < &MotorParameters::SEC, &STRUCT::KEY>, &set_field < &MotorParameters::SEC, &STRUCT::KEY> \
  }

#define SWUM_EFFECT(EFFECT, STRUCT, KEY, KIND, UNIT, MIN, MAX, DESC)            \
  ParameterSpec {                                                               \
    "effects." #EFFECT, #KEY, UNIT, DESC, ParameterKind::KIND, MIN, MAX, kNone, \
        &get_effect_field<&EffectParameters::EFFECT, &STRUCT::KEY>,             \
        &set_effect_field<&EffectParameters::EFFECT, &STRUCT::KEY>              \
  }
#define SWUM_EFFECT_SWITCH(EFFECT, STRUCT, WHAT) \
  SWUM_EFFECT(EFFECT, STRUCT, enabled, boolean, "-", 0.0, 1.0, "Enables the " WHAT " effect (docs/discrepancy.md)")

const std::array kSpecs{
    // [stator] Table 1, Table 2 (§7.2 reading), geometry §5
    SWUM_REAL(stator, StatorParameters, substrate_density_kg_m3, "kg/m^3", 100.0, 1e5,
              "Substrate (45 steel) density rho_s (Table 1)"),
    SWUM_REAL(stator, StatorParameters, substrate_youngs_modulus_pa, "Pa", 1e6, 1e13,
              "Substrate Young's modulus E_s (Table 1)"),
    SWUM_REAL(stator, StatorParameters, piezo_density_kg_m3, "kg/m^3", 100.0, 1e5, "PZT-8 density rho_p (Table 1)"),
    SWUM_REAL(stator, StatorParameters, piezo_c11_pa, "Pa", 1e6, 1e13, "PZT elastic stiffness c11^E (Table 1)"),
    SWUM_REAL(stator, StatorParameters, piezo_e31_c_m2, "C/m^2", -1e3, 1e3,
              "Piezoelectric constant e31 (Table 1; physical sign negative)"),
    SWUM_REAL(stator, StatorParameters, c111_pa, "Pa", -1e22, 1e22,
              "Second-order elastic constant c111 (Table 2, model_spec §7.2)"),
    SWUM_REAL(stator, StatorParameters, c1111_pa, "Pa", -1e22, 1e22,
              "Third-order elastic constant c1111 (Table 2; negative = softening)"),
    SWUM_REAL(stator, StatorParameters, e311_c_per_v_m, "C/(V m)", -1e6, 1e6,
              "Nonlinear electroelastic constant e311 (Table 2)"),
    SWUM_REAL(stator, StatorParameters, e3111_c_per_v_m, "C/(V m)", -1e6, 1e6,
              "Nonlinear electroelastic constant e3111 (Table 2)"),
    SWUM_REAL(stator, StatorParameters, damping_l1_n_s_m, "N s/m", 0.0, 1e6, "L1 modal damping C1 (Table 1)"),
    SWUM_REAL(stator, StatorParameters, damping_b2_n_s_m, "N s/m", 0.0, 1e6, "B2 modal damping C2 (Table 1)"),
    SWUM_REAL(stator, StatorParameters, substrate_thickness_mm, "mm", 1e-3, 1e3,
              "Substrate thickness ts (free choice, model_spec §5)"),
    SWUM_REAL(stator, StatorParameters, piezo_thickness_mm, "mm", 1e-3, 1e3,
              "Piezo patch thickness tp (free choice, model_spec §5)"),
    SWUM_CHOICE(stator, StatorParameters, geometry, kGeometryChoices,
                "L and hs from the target frequencies (model_spec §5) or explicit"),
    SWUM_REAL(stator, StatorParameters, target_l1_frequency_hz, "Hz", 1.0, 1e8,
              "Free-stator L1 natural frequency f1 used to compute L (paper: 39516 Hz)"),
    SWUM_REAL(stator, StatorParameters, target_b2_frequency_hz, "Hz", 1.0, 1e8,
              "Free-stator B2 natural frequency f2 used to compute hs (paper: 39469 Hz)"),
    SWUM_REAL(stator, StatorParameters, length_mm, "mm", 1e-3, 1e4,
              "Beam length L (only with geometry = \"explicit\")"),
    SWUM_REAL(stator, StatorParameters, half_height_mm, "mm", 1e-3, 1e4,
              "Beam half height hs (only with geometry = \"explicit\")"),
    SWUM_REAL(stator, StatorParameters, tip_lever_over_length, "-", -1.0, 1.0,
              "Tip lever L1/L of eq. 8: gT = phiB(L) + L1 phiB'(L) (literal: 0.1321)"),
    SWUM_REAL(stator, StatorParameters, clamped_capacitance_nf, "nF", 0.0, 1e6,
              "Clamped capacitance C0 of one phase: the current C0 dV/dt of the electrical port "
              "besides the motional current (docs/model.md, Electrical port; not in the paper); also the "
              "amplifier_droop effect's C0"),
    // [contact] Table 3
    SWUM_REAL(contact, ContactParameters, preload_n, "N", 0.0, 1e5, "Preload F_P (Table 3)"),
    SWUM_REAL(contact, ContactParameters, stiffness_n_m, "N/m", 0.0, 1e13,
              "Equivalent contact stiffness k_e (Table 3, eq. 16)"),
    SWUM_REAL(contact, ContactParameters, friction_coefficient, "-", 0.0, 10.0,
              "Stator/mover friction coefficient mu_c (Table 3)"),
    SWUM_REAL(contact, ContactParameters, erf_steepness_exponent, "-", -3.0, 15.0,
              "Exponent a of the erf friction law: kappa = 3.6 * 10^a s/m (eq. 22)"),
    SWUM_CHOICE(contact, ContactParameters, preload_application, kPreloadChoices,
                "Preload path into L1: both_ends = eq. 8 (gN F_N, gN = 2); back_end_constant = "
                "constant F_P at the back end + F_N at the tip (calibration, not in the paper)"),
    SWUM_REAL(contact, ContactParameters, tangential_stiffness_n_m, "N/m", 0.0, 1e11,
              "Tangential contact stiffness k_t of a Jenkins element (spring + Coulomb slider, "
              "extra state delta); 0 = rigid contact, the paper (calibration term)"),
    // [mover] Table 3
    SWUM_REAL(mover, MoverParameters, mass_kg, "kg", 1e-6, 1e4, "Mover mass m (Table 3)"),
    SWUM_REAL(mover, MoverParameters, damping_n_s_m, "N s/m", 0.0, 1e6, "Mover viscous damping c (Table 3)"),
    SWUM_REAL(mover, MoverParameters, guide_friction_coefficient, "-", 0.0, 10.0,
              "Linear-guide friction coefficient mu_s (Table 3, eq. 24)"),
    SWUM_REAL(mover, MoverParameters, gravity_m_s2, "m/s^2", 0.0, 100.0,
              "Gravity in the guide normal force mu_s (F_N + g m) (eq. 24)"),
    SWUM_REAL(mover, MoverParameters, guide_sign_smoothing_m_s, "m/s", 0.0, 10.0,
              "Width w of sign(v_m) ~ tanh(v_m/w) in eq. 24 (0 = exact sign)"),
    SWUM_CHOICE(mover, MoverParameters, guide_friction_model, kGuideChoices,
                "Guide friction: literal eqs. 24-25 with tanh sign, or exact Coulomb "
                "mu_s (F_N + g m) solved implicitly (stuck state; cheaper per step)"),
    // [options] §11
    SWUM_CHOICE(options, ModelOptions, paper_voltage_axis, kPaperAxisChoices,
                "How the paper's quoted voltages read (paper comparisons only): peak-to-peak (V0 = V/2) "
                "or amplitude (V0 = V); inputs are always terminal amplitudes"),
    SWUM_CHOICE(options, ModelOptions, tip_velocity_lever, kLeverChoices,
                "Tip velocity lever gTv: gT (passive) or phiB(L) (free tip, eq. 30)"),
    SWUM_CHOICE(options, ModelOptions, electrical_prefactors, kPrefactorChoices,
                "Prefactors of a1..a4: derived from the energy or the paper's 4x"),
    SWUM_CHOICE(options, ModelOptions, electrode_diagonals, kDiagonalChoices,
                "Which electrode diagonal carries phase A (swapped reverses direction)"),
    // [numerics]
    SWUM_REAL(numerics, NumericsParameters, time_step_ns, "ns", 1.0, 1e5,
              "Fixed step of the semi-implicit solver (default 1/(96 x 40 kHz))"),
    SWUM_CHOICE(numerics, NumericsParameters, friction_solver, kFrictionChoices,
                "Implicit friction solve: Coulomb projection or exact erf root"),
    SWUM_CHOICE(numerics, NumericsParameters, step_kernel, kStepKernelChoices,
                "Jenkins contact with implicit Coulomb guide: the hand-fused step or the generic "
                "one (same results to rounding; fused ~1.4x faster)"),
    SWUM_INT(numerics, NumericsParameters, quadrature_points, "-", 4.0, 4000.0,
             "Gauss-Legendre points per interval for the modal integrals"),
    SWUM_REAL(numerics, NumericsParameters, divergence_limit_um, "um", 1e-3, 1e9,
              "Runaway limit on the modal coordinates, sqrt(q1^2 + q2^2) (NaN guard resets above it)"),
    SWUM_REAL(numerics, NumericsParameters, divergence_speed_limit_m_s, "m/s", 1e-6, 1e9,
              "Runaway limit on the mover speed (NaN guard resets above it)"),
    // [amplifier] the output network (docs/amplifier.md)
    SWUM_REAL(amplifier, AmplifierParameters, source_resistance_ohm, "ohm", 0.0, 1e5,
              "Amplifier source resistance R_s of each phase (0 with both inductances 0: an ideal source; "
              "docs/amplifier.md); the "
              "amplifier_droop effect's R_s adds to it"),
    SWUM_REAL(amplifier, AmplifierParameters, series_inductance_uh, "uH", 0.0, 1e6,
              "Series inductance L_s between the amplifier and each phase (0 = none; series matching)"),
    SWUM_REAL(amplifier, AmplifierParameters, parallel_inductance_uh, "uH", 0.0, 1e6,
              "Inductance L_p across each phase's terminals (0 = none; compensates C0)"),
    // [effects.*] candidate effects of the discrepancy workflow (docs/discrepancy.md)
    SWUM_EFFECT_SWITCH(electroelastic, ElectroelasticEffect, "non-linear electroelasticity"),
    SWUM_EFFECT(electroelastic, ElectroelasticEffect, scale, real, "-", -5.0, 5.0,
                "Adds scale x the reference Table-2 constants (li2019.toml) to c111, c1111, "
                "e311, e3111 (free parameter)"),
    SWUM_EFFECT_SWITCH(thermal, ThermalEffect, "stator temperature"),
    SWUM_EFFECT(thermal, ThermalEffect, thermal_resistance_k_per_w, real, "K/W", 0.0, 1e3,
                "Steady temperature rise per watt of modal damping power C1 q1'^2 + C2 q2'^2 "
                "(free parameter)"),
    SWUM_EFFECT(thermal, ThermalEffect, time_constant_s, real, "s", 1e-3, 1e6,
                "Thermal time constant tau of dT/dt = (R_th P - T)/tau (fixed)"),
    SWUM_EFFECT(thermal, ThermalEffect, stiffness_coefficient_per_k, real, "1/K", -0.1, 0.1,
                "Relative change of K1, K2 per kelvin (fixed)"),
    SWUM_EFFECT(thermal, ThermalEffect, damping_coefficient_per_k, real, "1/K", -0.1, 1.0,
                "Relative change of C1, C2 per kelvin (fixed)"),
    SWUM_EFFECT_SWITCH(wear, WearEffect, "friction-pair wear"),
    SWUM_EFFECT(wear, WearEffect, friction_change, real, "-", -0.9, 5.0,
                "Relative change d of mu_c after run-in: mu_c (1 + d (1 - exp(-s/s0))) "
                "(free parameter)"),
    SWUM_EFFECT(wear, WearEffect, run_in_distance_m, real, "m", 1e-3, 1e6,
                "Run-in sliding (mover travel) distance s0 (fixed)"),
    SWUM_EFFECT_SWITCH(preload, PreloadEffect, "preload error"),
    SWUM_EFFECT(preload, PreloadEffect, preload_factor, real, "-", 0.05, 5.0,
                "F_P -> f F_P and k_e -> f^(1/3) k_e (Hertzian contact) (free parameter)"),
    SWUM_EFFECT_SWITCH(guide_friction, GuideFrictionEffect, "extra guide friction"),
    SWUM_EFFECT(guide_friction, GuideFrictionEffect, extra_coefficient, real, "-", -1.0, 5.0,
                "Added to mu_s (eq. 24; result clamped at 0) (free parameter)"),
    SWUM_EFFECT_SWITCH(amplifier_droop, AmplifierDroopEffect, "amplifier droop"),
    SWUM_EFFECT(amplifier_droop, AmplifierDroopEffect, source_resistance_ohm, real, "ohm", 0.0, 1e5,
                "Amplifier source resistance R_s (free parameter); C0 is stator.clamped_capacitance_nf"),
};

#undef SWUM_EFFECT_SWITCH
#undef SWUM_EFFECT
#undef SWUM_REAL
#undef SWUM_INT
#undef SWUM_CHOICE

std::string number_text(double v) {
  // Shortest text that reads back to the same double.
  char buffer[64];
  if (v == std::floor(v) && std::abs(v) < 1e7) {
    std::snprintf(buffer, sizeof buffer, "%.1f", v);
    return buffer;
  }
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buffer, sizeof buffer, "%.*g", precision, v);
    if (std::strtod(buffer, nullptr) == v) break;
  }
  std::string s(buffer);
  // Make reals look like TOML floats.
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

}  // namespace

MotorParameters linearised(MotorParameters parameters) {
  parameters.stator.c111_pa = 0.0;
  parameters.stator.c1111_pa = 0.0;
  parameters.stator.e311_c_per_v_m = 0.0;
  parameters.stator.e3111_c_per_v_m = 0.0;
  return parameters;
}

MotorParameters with_static_effects(MotorParameters p) {
  const EffectParameters& e = p.effects;
  if (e.electroelastic.enabled) {
    const ReferenceNonlinearConstants ref;
    const double k = e.electroelastic.scale;
    p.stator.c111_pa += k * ref.c111_pa;
    p.stator.c1111_pa += k * ref.c1111_pa;
    p.stator.e311_c_per_v_m += k * ref.e311_c_per_v_m;
    p.stator.e3111_c_per_v_m += k * ref.e3111_c_per_v_m;
  }
  if (e.preload.enabled) {
    p.contact.preload_n *= e.preload.preload_factor;
    p.contact.stiffness_n_m *= std::cbrt(e.preload.preload_factor);
  }
  if (e.guide_friction.enabled) {
    p.mover.guide_friction_coefficient = std::max(0.0, p.mover.guide_friction_coefficient +
                                                           e.guide_friction.extra_coefficient);
  }
  return p;
}

std::string ParameterSpec::name() const { return std::string(section) + "." + std::string(key); }

std::string quoted(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 2);
  out.push_back('"');
  out.append(text);
  out.push_back('"');
  return out;
}

std::span<const ParameterSpec> parameter_specs() { return kSpecs; }

const ParameterSpec* find_parameter_spec(std::string_view section, std::string_view key) {
  for (const auto& spec : kSpecs) {
    if (spec.section == section && spec.key == key) return &spec;
  }
  return nullptr;
}

std::string parameter_section_names() {
  std::string list;
  std::string_view last;
  for (const auto& spec : kSpecs) {
    if (spec.section == last) continue;
    last = spec.section;
    list += list.empty() ? "" : ", ";
    list += std::string(last);
  }
  return list;
}

std::string format_parameter_value(const ParameterSpec& spec, double value) {
  switch (spec.kind) {
    case ParameterKind::choice: {
      const auto index = static_cast<std::size_t>(value);
      if (index < spec.choices.size()) return quoted(spec.choices[index]);
      return "<invalid>";
    }
    case ParameterKind::boolean: return value != 0.0 ? "true" : "false";
    case ParameterKind::integer: {
      char buffer[32];
      std::snprintf(buffer, sizeof buffer, "%lld", static_cast<long long>(value));
      return buffer;
    }
    case ParameterKind::real: break;
  }
  return number_text(value);
}

void validate_parameters(const MotorParameters& parameters, std::string_view source_name) {
  for (const auto& spec : kSpecs) {
    const double v = spec.get(parameters);
    std::string problem;
    if (!std::isfinite(v)) {
      problem = "is not a finite number";
    } else if (v < spec.min_value || v > spec.max_value) {
      problem = "value " + format_parameter_value(spec, v) + " is out of range";
    } else if (spec.kind == ParameterKind::integer && v != std::floor(v)) {
      problem = "must be an integer";
    }
    if (problem.empty()) continue;
    std::string allowed;
    if (spec.kind == ParameterKind::choice) {
      allowed = "one of";
      for (auto c : spec.choices) allowed.append(" ").append(quoted(c));
    } else if (spec.kind == ParameterKind::boolean) {
      allowed = "true or false";
    } else {
      allowed = std::string("[") + format_parameter_value(spec, spec.min_value) + ", " +
                format_parameter_value(spec, spec.max_value) + "] " + std::string(spec.unit);
    }
    throw ParameterError(std::string(source_name) + ": " + std::string(spec.section) + "." + std::string(spec.key) +
                         " " + problem + " (allowed: " + allowed + ")");
  }
  const auto& s = parameters.stator;
  if (s.geometry == GeometryMode::explicit_size && s.half_height_mm >= s.length_mm) {
    throw ParameterError(std::string(source_name) + ": stator.half_height_mm must be smaller than stator.length_mm");
  }
  const std::string network_problem = check_output_network(parameters);
  if (!network_problem.empty()) throw ParameterError(std::string(source_name) + ": " + network_problem);
}

std::string render_parameters_markdown() {
  const MotorParameters defaults{};
  std::string out;
  out += "# Model parameters\n\n";
  out += "Generated from the parameter table in `src/model/parameters.cpp` "
         "(`swum::render_parameters_markdown()`); a test checks that this file matches it.\n"
         "Parameter files are TOML with one table per section; unknown keys, wrong types, "
         "NaN/Inf and out-of-range values are errors. Integers are accepted for real keys.\n"
         "Equation numbers refer to Li et al. 2019 (MSSP), sections (§) to "
         "[model_spec.md](model_spec.md).\n"
         "The `[effects.*]` tables are the candidate effects of the discrepancy workflow "
         "([discrepancy.md](discrepancy.md)); all are off by default.\n"
         "One C0: the amplifier-droop effect's clamped capacitance is the stator's "
         "`clamped_capacitance_nf` (the same capacitance of each phase the electrical port sees). "
         "Files written before the two were one also set `[effects.amplifier_droop] "
         "clamped_capacitance_nf`: such a key is read when it repeats the stator's value and refused "
         "when it differs.\n"
         "\n## Voltages\n\n"
         "Every voltage a user reads or writes (the model's input, `--amplitude-v`, the registers, CAN "
         "signals, CSV columns `amplitude_v`, HTTP fields, plots) is the **terminal voltage amplitude of one "
         "phase**, zero-to-peak, in V: phase A is driven at `V0 sin(wt)`, so a board sees `2 V0` peak-to-peak "
         "and draws about `w C0 V0` of reactive current per phase. No key of a motor file changes that "
         "meaning.\n\n"
         "The paper's figures label their voltage axis \"Vpp\" although the calibrated model matches them "
         "only when that number is read as the amplitude (model_spec §9.3 reading (i), "
         "[validation.md](validation.md)). Which reading a motor's calibration rests on is a property of the "
         "calibration, not of the drive, so it is a key of its own, `options.paper_voltage_axis`: "
         "`\"amplitude\"` (config/li2019.toml, li2019_thermal.toml: the paper's 400 is a 400 V amplitude) "
         "or `\"peak_to_peak\"` (li2019_literal.toml and the default: the paper's 400 is a 200 V "
         "amplitude). It is read only where the model is compared with the paper's numbers (the paper-fact "
         "checks, `swum validate`'s curves, facts files such as config/li2019_facts.toml). With the literal "
         "motor a user therefore drives `--amplitude-v 200` where the paper says \"400 Vpp\"; with the "
         "calibrated motor the numbers are the paper's. The key that did both jobs before, "
         "`options.voltage_convention`, is refused with a one-line error naming its replacement: a file "
         "that says it would otherwise change the meaning of its users' inputs silently.\n";
  std::string_view section;
  for (const auto& spec : kSpecs) {
    if (spec.section != section) {
      section = spec.section;
      out += std::string("\n## [") + std::string(section) + "]\n\n";
      out += "| key | unit | default | allowed | description |\n";
      out += "|---|---|---|---|---|\n";
    }
    std::string allowed;
    if (spec.kind == ParameterKind::choice) {
      for (auto c : spec.choices) {
        if (!allowed.empty()) allowed += ", ";
        allowed.append("`").append(quoted(c)).append("`");
      }
    } else if (spec.kind == ParameterKind::boolean) {
      allowed = "`true`, `false`";
    } else {
      allowed = format_parameter_value(spec, spec.min_value) + " .. " + format_parameter_value(spec, spec.max_value);
    }
    out += "| `" + std::string(spec.key) + "` | " + std::string(spec.unit) + " | `" +
           format_parameter_value(spec, spec.get(defaults)) + "` | " + allowed + " | " + std::string(spec.description) +
           " |\n";
  }
  return out;
}

}  // namespace swum
