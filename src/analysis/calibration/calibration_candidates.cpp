#include "analysis/calibration/calibration_candidates.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace swum {
namespace {

// In order of preference (calibration.h, step 1): first what differs most between motors of one
// design and moves a sweep most - preload (set at assembly), L1 damping, contact friction, the
// non-linear constants that set the drift with voltage, the tip's tangential compliance - then
// the normal contact stiffness and the L1 frequency (both move the stiffened resonance, so
// usually only one of them can join), then the rest.
// Spreads: what a motor of this design is known to before measuring it (docs/calibration.md,
// "The candidates"). The non-linear constants are known to a factor (Table 2 needed a reading
// of its exponents, and the calibration moved c1111 by 3.4x): 50 %. Damping and stiffnesses of
// an assembled motor: 20-30 %. Preload (a spring set at assembly) and friction coefficients:
// 10-25 %. Natural frequencies of a stator as made: 100 Hz.
constexpr std::array kCandidates{
    CalibrationCandidate{"contact.preload_n", "preload (dead zone, speed level, stiffened resonance)", 0.1, 0.0, 0.0,
                         3.0, 0.1},
    CalibrationCandidate{"stator.damping_l1_n_s_m", "L1 modal damping (peak height and width)", 0.2, 0.0, 0.0, 3.0,
                         0.1},
    CalibrationCandidate{"contact.friction_coefficient", "contact friction mu_c (speed under load)", 0.1, 0.0, 0.0, 3.0,
                         0.1},
    CalibrationCandidate{"stator.c1111_pa", "amplitude softening of L1 (peak drift with voltage)", 0.5, 0.0, 0.85e17,
                         3.0, 0.05},
    CalibrationCandidate{"stator.e3111_c_per_v_m", "voltage-dependent stiffness, cubic (drift with voltage)", 0.5, 0.0,
                         6.4235e-3, 3.0, 0.05},
    CalibrationCandidate{"contact.tangential_stiffness_n_m", "tangential compliance of the tip (dead-zone onset)", 0.3,
                         0.0, 0.0, 3.0, 0.1},
    CalibrationCandidate{"contact.stiffness_n_m", "normal contact stiffness k_e (stiffened resonance)", 0.2, 0.0, 0.0,
                         3.0, 0.1},
    CalibrationCandidate{"stator.target_l1_frequency_hz", "L1 natural frequency (peak position)", 0.0, 100.0, 0.0, 10.0,
                         0.1},
    CalibrationCandidate{"stator.damping_b2_n_s_m", "B2 modal damping (tangential amplitude)", 0.2, 0.0, 0.0, 3.0, 0.1},
    CalibrationCandidate{"stator.target_b2_frequency_hz", "B2 natural frequency", 0.0, 100.0, 0.0, 10.0, 0.1},
    CalibrationCandidate{"stator.substrate_thickness_mm",
                         "substrate thickness (modal mass and stiffness at fixed natural frequencies)", 0.2, 0.0, 0.0,
                         3.0, 0.1},
    CalibrationCandidate{"mover.guide_friction_coefficient", "linear-guide friction mu_s (dead-zone width)", 0.25, 0.0,
                         0.0, 3.0, 0.1},
    CalibrationCandidate{"mover.damping_n_s_m", "mover viscous damping (speed level)", 0.25, 0.0, 0.0, 3.0, 0.1},
    CalibrationCandidate{"stator.c111_pa", "quadratic stiffness of L1", 0.5, 0.0, 1.4583e12, 3.0, 0.05},
    CalibrationCandidate{"stator.e311_c_per_v_m", "voltage-dependent stiffness, quadratic", 0.5, 0.0, 3.3142e-6, 3.0,
                         0.05},
    CalibrationCandidate{"mover.mass_kg", "mover mass (guide normal force; nothing else in a steady state)", 0.1, 0.0,
                         0.0, 3.0, 0.1},
};

const ParameterSpec& spec_of(const CalibrationCandidate& c) {
  const std::string_view name = c.name;
  const std::size_t dot = name.find('.');
  const ParameterSpec* spec = find_parameter_spec(name.substr(0, dot), name.substr(dot + 1));
  if (spec == nullptr) throw std::logic_error("parameter table has no " + std::string(name));
  return *spec;
}

// Why the candidate does not apply to `prior` ("" when it does).
std::string not_applicable(const CalibrationCandidate& c, const MotorParameters& prior) {
  const std::string_view name = c.name;
  if (name.starts_with("stator.target_") && prior.stator.geometry != GeometryMode::from_frequencies) {
    return "the natural frequencies are not parameters with stator.geometry = \"explicit\"";
  }
  if (name == "contact.tangential_stiffness_n_m" && !(prior.contact.tangential_stiffness_n_m > 0.0)) {
    return "the contact is rigid (tangential_stiffness_n_m = 0); a Jenkins stiffness is a different contact law";
  }
  if (c.absolute_spread <= 0.0 && c.fallback_magnitude <= 0.0 && spec_of(c).get(prior) == 0.0) {
    return "its prior value is 0, so it has no scale";
  }
  return "";
}

}  // namespace

std::span<const CalibrationCandidate> calibration_candidates() { return kCandidates; }

const CalibrationCandidate* find_calibration_candidate(std::string_view name) {
  for (const CalibrationCandidate& c : kCandidates) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

std::string calibration_candidate_names() {
  std::string out;
  for (const CalibrationCandidate& c : kCandidates) out += (out.empty() ? "" : ", ") + std::string(c.name);
  return out;
}

std::vector<const CalibrationCandidate*> applicable_candidates(const MotorParameters& prior) {
  std::vector<const CalibrationCandidate*> out;
  for (const CalibrationCandidate& c : kCandidates) {
    if (not_applicable(c, prior).empty()) out.push_back(&c);
  }
  return out;
}

FreeParameter calibration_free_parameter(const CalibrationCandidate& c, const MotorParameters& prior) {
  if (const std::string why = not_applicable(c, prior); !why.empty()) {
    throw std::invalid_argument(std::string(c.name) + " cannot be fitted: " + why);
  }
  const ParameterSpec& spec = spec_of(c);
  const double value = spec.get(prior);
  const double magnitude = value != 0.0 ? std::abs(value) : c.fallback_magnitude;
  const double spread = c.absolute_spread > 0.0 ? c.absolute_spread : c.relative_spread * magnitude;
  double lower = value - c.bound_spreads * spread;
  double upper = value + c.bound_spreads * spread;
  // Stay on the prior's side of zero: a sign change is a different motor, not a calibration.
  if (value > 0.0) lower = std::max(lower, c.min_fraction * value);
  if (value < 0.0) upper = std::min(upper, c.min_fraction * value);
  lower = std::max(lower, spec.min_value);
  upper = std::min(upper, spec.max_value);
  const ParameterSpec* s = &spec;
  return {spec.name(),
          std::string(spec.unit),
          value,
          spread,
          lower,
          upper,
          [s](MotorParameters& p, double v) { s->set(p, v); }};
}

}  // namespace swum
