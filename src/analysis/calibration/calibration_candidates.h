// The base parameters `swum calibrate` may fit (docs/calibration.md): each a key of the
// parameter table with the spread it is known to a priori for a motor of this design (the
// unit the data is asked to resolve: a parameter whose standard error is not below half of it
// is not identifiable) and how far a fit may move it. Not in the list: the geometry and the
// material constants a maker's data sheet gives, and choices/numerics.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/fit/free_parameter.h"
#include "model/parameters.h"

namespace swum {

struct CalibrationCandidate {
  std::string_view name;  // "section.key" of the parameter table
  std::string_view why;   // what it changes in a sweep (one line for reports)
  // Prior spread: relative_spread x |prior|, or absolute_spread when that is > 0, or
  // relative_spread x fallback_magnitude when the prior is 0.
  double relative_spread = 0.0;
  double absolute_spread = 0.0;
  double fallback_magnitude = 0.0;
  // Fit bounds: prior -/+ bound_spreads x spread, kept on the prior's side of zero (at least
  // min_fraction x |prior| from it) and inside the parameter's documented range.
  double bound_spreads = 3.0;
  double min_fraction = 0.1;
};

// In order of preference (calibration_candidates.cpp says why).
[[nodiscard]] std::span<const CalibrationCandidate> calibration_candidates();
// nullptr if `name` is not a candidate.
[[nodiscard]] const CalibrationCandidate* find_calibration_candidate(std::string_view name);
[[nodiscard]] std::string calibration_candidate_names();  // "stator.c1111_pa, ..."

// The candidates that apply to `prior` (the target frequencies only with geometry =
// "from_frequencies", the tangential stiffness only for a Jenkins contact, k_t > 0).
[[nodiscard]] std::vector<const CalibrationCandidate*> applicable_candidates(const MotorParameters& prior);

// The candidate as a fit's free parameter around `prior` (origin = prior value, scale = spread).
// Throws std::invalid_argument when it does not apply to `prior` (saying why).
[[nodiscard]] FreeParameter calibration_free_parameter(const CalibrationCandidate& candidate,
                                                       const MotorParameters& prior);

}  // namespace swum
