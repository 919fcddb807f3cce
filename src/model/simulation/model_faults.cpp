#include "model/simulation/model_faults.h"

#include <cmath>
#include <sstream>

namespace swum {

bool ModelFaults::nominal() const {
  return phase_a_gain == 1.0 && phase_b_gain == 1.0 && preload_factor == 1.0 && guide_friction_factor == 1.0 && !jammed;
}

std::string check(const ModelFaults& f) {
  std::ostringstream out;
  out.precision(17);
  auto range = [&out](const char* name, double value, double max) {
    if (value >= 0.0 && value <= max) return false;  // false for NaN too
    out << name << " = " << value << " outside [0, " << max << "]";
    return true;
  };
  if (range("phase_a_gain", f.phase_a_gain, kMaxPhaseGain) || range("phase_b_gain", f.phase_b_gain, kMaxPhaseGain) ||
      range("preload_factor", f.preload_factor, 1.0) ||
      range("guide_friction_factor", f.guide_friction_factor, kMaxGuideFrictionFactor)) {
    return out.str();
  }
  if (std::isinf(f.jam_position_m)) {
    out << "jam_position_m = " << f.jam_position_m << " is not finite (NaN: the current position)";
    return out.str();
  }
  return {};
}

}  // namespace swum
