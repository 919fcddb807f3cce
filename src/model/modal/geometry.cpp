#include "model/modal/geometry.h"

#include <cmath>
#include <numbers>

#include "model/modal/mode_shapes.h"

namespace swum {

double laminate_wave_speed_m_s(const StatorParameters& s) {
  const double ts = s.substrate_thickness_mm * 1e-3;
  const double tp = s.piezo_thickness_mm * 1e-3;
  return std::sqrt((s.substrate_youngs_modulus_pa * ts + 2.0 * s.piezo_c11_pa * tp) /
                   (s.substrate_density_kg_m3 * ts + 2.0 * s.piezo_density_kg_m3 * tp));
}

StatorGeometry calibrate_geometry(const StatorParameters& s) {
  const double cl = laminate_wave_speed_m_s(s);
  const double bl = free_free_b2_root();
  StatorGeometry g;
  g.substrate_thickness_m = s.substrate_thickness_mm * 1e-3;
  g.piezo_thickness_m = s.piezo_thickness_mm * 1e-3;
  g.length_m = cl / (2.0 * s.target_l1_frequency_hz);
  g.half_height_m = std::sqrt(3.0) * 2.0 * std::numbers::pi * s.target_b2_frequency_hz * g.length_m * g.length_m /
                    (bl * bl * cl);
  return g;
}

StatorGeometry stator_geometry(const StatorParameters& s) {
  if (s.geometry == GeometryMode::from_frequencies) return calibrate_geometry(s);
  StatorGeometry g;
  g.substrate_thickness_m = s.substrate_thickness_mm * 1e-3;
  g.piezo_thickness_m = s.piezo_thickness_mm * 1e-3;
  g.length_m = s.length_mm * 1e-3;
  g.half_height_m = s.half_height_mm * 1e-3;
  return g;
}

}  // namespace swum
