// A parameter a fit may move (parameter_fit.h): where it is written in the parameter set, the
// unit the solver works in, and its bounds. The discrepancy workflow fits the free parameters
// of candidate effects (candidate_effects.h), `swum calibrate` base parameters of the
// parameter table (calibration_candidates.h); the solver does not know which.
#pragma once

#include <functional>
#include <string>

#include "model/parameters.h"

namespace swum {

struct FreeParameter {
  std::string name;  // "section.key" of the parameter table, e.g. "contact.preload_n"
  std::string unit;
  // The solver works in theta = (value - origin) / scale: every parameter in units of the
  // size the data is asked to resolve (scale may be negative; finite-difference steps are
  // 0.1 theta).
  double origin = 0.0;
  double scale = 1.0;
  double lower = 0.0;  // bounds of the value
  double upper = 0.0;
  // Writes `value` into the parameter set (and enables what it belongs to).
  std::function<void(MotorParameters&, double)> apply;
};

}  // namespace swum
