// Stator geometry (model_spec §1.1, §5). The paper gives only f1 and f2; L and hs follow from
// them for a chosen ts, tp.
#pragma once

#include "model/parameters.h"

namespace swum {

struct StatorGeometry {
  double length_m = 0.0;               // L
  double half_height_m = 0.0;          // hs (beam height 2 hs, along y)
  double substrate_thickness_m = 0.0;  // ts (along z)
  double piezo_thickness_m = 0.0;      // tp (one patch, along z)
};

// Longitudinal wave speed of the laminate, cL^2 = (Es ts + 2 c11 tp)/(rho_s ts + 2 rho_p tp).
[[nodiscard]] double laminate_wave_speed_m_s(const StatorParameters& stator);

// §5 calibration: L = cL/(2 f1) (omega1^2 = K1/M1 = (pi cL/L)^2) and
// hs = sqrt(3) 2 pi f2 L^2 / ((beta2 L)^2 cL) (omega2^2 = K2/M2 = beta2^4 hs^2 cL^2/3),
// using stator.target_l1_frequency_hz, target_b2_frequency_hz, substrate/piezo thickness.
// Exact for the Appendix-A mass and stiffness with the exact free-free shapes.
[[nodiscard]] StatorGeometry calibrate_geometry(const StatorParameters& stator);

// calibrate_geometry() or the explicit length/half height, per stator.geometry.
[[nodiscard]] StatorGeometry stator_geometry(const StatorParameters& stator);

}  // namespace swum
