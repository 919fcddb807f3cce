// Modal constants of eqs. (14)-(15) (Appendix A, model_spec §1.5-1.6), computed by
// Gauss-Legendre quadrature from geometry and material.
#pragma once

#include <array>

#include "model/modal/geometry.h"
#include "model/parameters.h"

namespace swum {

// Electrical coefficient X(t) = group_a * V_A(t)^n + group_b * V_B(t)^n (n = 1 for a0, a2,
// a4, b0, b2, b4; n = 2 for a1, a3, b1, b3), V in volts, SI throughout.
struct ElectricalCoefficient {
  double group_a = 0.0;
  double group_b = 0.0;
};

struct ModalConstants {
  StatorGeometry geometry;
  double wave_speed_m_s = 0.0;        // cL
  double substrate_area_m2 = 0.0;     // As = 2 hs ts
  double patch_area_m2 = 0.0;         // Ap = hs tp (one patch)
  double substrate_inertia_m4 = 0.0;  // Is = 2 ts hs^3/3
  double mass_per_length_kg_m = 0.0;  // m_l = rho_s As + 4 rho_p Ap

  double phi_b_tip = 0.0;              // phiB(L) = 1.998449
  double phi_b_slope_tip_per_m = 0.0;  // phiB'(L)
  double tip_lever_m = 0.0;            // L1

  double m1_kg = 0.0, k1_n_m = 0.0, c1_n_s_m = 0.0;  // eq. 14
  double m2_kg = 0.0, k2_n_m = 0.0, c2_n_s_m = 0.0;  // eq. 15
  double alpha1 = 0.0;                               // 6 Ap Int phiL'^3 (dimensionless)
  double beta1_per_m = 0.0;                          // 8 Ap Int phiL'^4
  double beta2_per_m = 0.0;                          // hp^4 Ap/10 Int phiB''^4
  double g_n = 0.0;                                  // lever of F_N on q1: phiL(0) - phiL(L) = 2 (both_ends) or
                                                     // -phiL(L) = 1 (back_end_constant)
  double g_np = 0.0;                                 // lever of the constant F_P on q1: 0 or phiL(0) = 1
  double g_t = 0.0;                                  // phiB(L) + L1 phiB'(L)
  double g_tv = 0.0;                                 // tip velocity lever (gT or phiB(L), option)

  // a0 and b0 include e31 (N/V); a1..a4, b1..b4 are multiplied by e311/e3111 in eqs. 14-15.
  std::array<ElectricalCoefficient, 5> a{};
  std::array<ElectricalCoefficient, 5> b{};

  double kappa_s_per_m = 0.0;             // erf steepness 3.6 * 10^a
  double drive_amplitude_per_volt = 0.0;  // V0 per input volt: 1 (inputs are terminal amplitudes)

  double f_l1_hz = 0.0;               // sqrt(K1/M1)/2pi
  double f_b2_hz = 0.0;               // sqrt(K2/M2)/2pi
  double f_l1_full_contact_hz = 0.0;  // sqrt((K1 + gN k_e)/M1)/2pi
  double f_b2_stick_hz = 0.0;         // sqrt((K2 + gT gTv k_t)/M2)/2pi (Jenkins stick; = f_b2 if k_t = 0)
  double static_q1_m = 0.0;           // preload equilibrium (V = 0), §2.1
};

[[nodiscard]] ModalConstants compute_modal_constants(const MotorParameters& parameters);

}  // namespace swum
