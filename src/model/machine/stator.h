// Stator modal forces, eqs. (14)-(15) (model_spec §1.4-1.5), without damping and interface
// forces. Each mode's force is a cubic in its coordinate whose coefficients are linear or
// quadratic in the two phase voltages; the products with c111, c1111, e311, e3111 are folded
// once so the per-step cost is ~20 flops.
#pragma once

#include "model/modal/modal_constants.h"
#include "model/parameters.h"

namespace swum {

// f(q, V_A, V_B) = c0 + c1 q + c2 q^2 - k3 q^3 with
//   c0 = lin0 . V + sq0 . V^2,  c1 = lin1 . V + sq1 . V^2 - k,  c2 = lin2 . V - k2.
struct ModeForceCoefficients {
  double lin0_a = 0.0, lin0_b = 0.0;  // a0 / b0
  double sq0_a = 0.0, sq0_b = 0.0;    // e311 a1 / e311 b1
  double lin1_a = 0.0, lin1_b = 0.0;  // e311 a2 / e311 b2
  double sq1_a = 0.0, sq1_b = 0.0;    // e3111 a3 / e3111 b3
  double lin2_a = 0.0, lin2_b = 0.0;  // e3111 a4 / e3111 b4
  double k = 0.0;                     // K1 / K2
  double k2 = 0.0;                    // c111 alpha1 / 0 (no c111 term in eq. 15)
  double k3 = 0.0;                    // c1111 beta1 / c1111 beta2
};

struct StatorForceCoefficients {
  ModeForceCoefficients l1;  // eq. 14
  ModeForceCoefficients b2;  // eq. 15
};

[[nodiscard]] StatorForceCoefficients make_stator_force_coefficients(const ModalConstants& constants,
                                                                     const StatorParameters& stator);

// Generalised modal force (N) of one mode at coordinate q (m) and phase voltages (V).
[[nodiscard]] inline double modal_force_n(const ModeForceCoefficients& m, double q, double va, double vb) {
  const double va2 = va * va;
  const double vb2 = vb * vb;
  const double c0 = m.lin0_a * va + m.lin0_b * vb + m.sq0_a * va2 + m.sq0_b * vb2;
  const double c1 = m.lin1_a * va + m.lin1_b * vb + m.sq1_a * va2 + m.sq1_b * vb2 - m.k;
  const double c2 = m.lin2_a * va + m.lin2_b * vb - m.k2;
  return c0 + q * (c1 + q * (c2 - m.k3 * q));
}

// Both modes at once with a two-lane double vector (SSE2 / NEON through the GCC/Clang vector
// extension; lane 0 = L1, lane 1 = B2). Same arithmetic as modal_force_n, ~1/3 of the
// instructions: the fixed-step hot loop uses this.
using DoublePair = double __attribute__((vector_size(16)));

struct PairedForceCoefficients {
  DoublePair lin0_a, lin0_b, sq0_a, sq0_b, lin1_a, lin1_b, sq1_a, sq1_b, lin2_a, lin2_b;
  DoublePair k, k2, k3;
};

[[nodiscard]] PairedForceCoefficients make_paired_force_coefficients(const StatorForceCoefficients& c);

[[nodiscard]] inline DoublePair modal_forces_n(const PairedForceCoefficients& m, DoublePair q, double va, double vb) {
  const DoublePair a = {va, va};
  const DoublePair b = {vb, vb};
  const DoublePair a2 = a * a;
  const DoublePair b2 = b * b;
  const DoublePair c0 = m.lin0_a * a + m.lin0_b * b + m.sq0_a * a2 + m.sq0_b * b2;
  const DoublePair c1 = m.lin1_a * a + m.lin1_b * b + m.sq1_a * a2 + m.sq1_b * b2 - m.k;
  const DoublePair c2 = m.lin2_a * a + m.lin2_b * b - m.k2;
  return c0 + q * (c1 + q * (c2 - m.k3 * q));
}

}  // namespace swum
