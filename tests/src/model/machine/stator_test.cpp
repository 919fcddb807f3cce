#include "model/machine/stator.h"

#include <gtest/gtest.h>

#include <cmath>

#include "model/motor_model.h"

namespace swum {
namespace {

TEST(StatorForces, PairedEqualsScalar) {
  const MotorModel model{MotorParameters{}};
  const auto& s = model.coefficients().stator;
  const auto paired = make_paired_force_coefficients(s);
  for (double q : {-3e-6, -1e-8, 0.0, 4.2e-8, 2.5e-6}) {
    for (double va : {-200.0, 0.0, 150.0}) {
      const double vb = 0.7 * va - 30.0;
      const DoublePair f = modal_forces_n(paired, DoublePair{q, 0.5 * q}, va, vb);
      EXPECT_NEAR(f[0], modal_force_n(s.l1, q, va, vb), 1e-12 * (1 + std::abs(f[0])));
      EXPECT_NEAR(f[1], modal_force_n(s.b2, 0.5 * q, va, vb), 1e-12 * (1 + std::abs(f[1])));
    }
  }
}

TEST(StatorForces, EquationFourteenTermByTerm) {
  const MotorParameters p{};
  const MotorModel model(p);
  const auto& c = model.constants();
  const auto& st = p.stator;
  const double q = 1.3e-6;
  const double va = 120.0;
  const double vb = -80.0;
  auto lin = [&](const ElectricalCoefficient& x) { return x.group_a * va + x.group_b * vb; };
  auto sq = [&](const ElectricalCoefficient& x) { return x.group_a * va * va + x.group_b * vb * vb; };
  const double expected_l1 = lin(c.a[0]) + st.e311_c_per_v_m * sq(c.a[1]) +
                             (st.e311_c_per_v_m * lin(c.a[2]) + st.e3111_c_per_v_m * sq(c.a[3])) * q +
                             st.e3111_c_per_v_m * lin(c.a[4]) * q * q - c.k1_n_m * q - st.c111_pa * c.alpha1 * q * q -
                             st.c1111_pa * c.beta1_per_m * q * q * q;
  EXPECT_NEAR(modal_force_n(model.coefficients().stator.l1, q, va, vb), expected_l1, 1e-12 * std::abs(expected_l1));
  const double expected_b2 = lin(c.b[0]) + st.e311_c_per_v_m * sq(c.b[1]) +
                             (st.e311_c_per_v_m * lin(c.b[2]) + st.e3111_c_per_v_m * sq(c.b[3])) * q +
                             st.e3111_c_per_v_m * lin(c.b[4]) * q * q - c.k2_n_m * q -
                             st.c1111_pa * c.beta2_per_m * q * q * q;
  EXPECT_NEAR(modal_force_n(model.coefficients().stator.b2, q, va, vb), expected_b2, 1e-12 * std::abs(expected_b2));
}

}  // namespace
}  // namespace swum
