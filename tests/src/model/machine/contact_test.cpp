#include "model/machine/contact.h"

#include <gtest/gtest.h>

#include <cmath>

namespace swum {
namespace {

TEST(NormalForce, SeparationAndPreload) {
  EXPECT_DOUBLE_EQ(normal_force_n(24.8, 2.58e7, 0.0), 24.8);
  EXPECT_NEAR(normal_force_n(24.8, 2.58e7, -1e-6), 24.8 + 25.8, 1e-9);          // tip pushed in
  EXPECT_DOUBLE_EQ(normal_force_n(24.8, 2.58e7, 24.8 / 2.58e7 * 1.0001), 0.0);  // separated
}

TEST(ErfFriction, SaturatesToCoulomb) {
  EXPECT_NEAR(erf_friction_n(8.0, 3.6e6, 5e-7), 8.0 * 0.99, 0.01);
  EXPECT_NEAR(erf_friction_n(8.0, 3.6e6, -1.0), -8.0, 1e-12);
  EXPECT_DOUBLE_EQ(erf_friction_n(0.0, 3.6e6, 1.0), 0.0);
}

TEST(CoulombProjection, SticksInsideConeSlipsOutside) {
  const double compliance = 1e-3;  // m/s per N
  const double limit = 5.0;
  // Stick: the force that cancels the relative velocity is inside the cone.
  const double stick = coulomb_projection_friction_n(2e-3, compliance, limit);
  EXPECT_NEAR(stick, 2.0, 1e-12);
  EXPECT_NEAR(2e-3 - compliance * stick, 0.0, 1e-15);  // v_rel after the step = 0
  // Slip: saturates at the limit and keeps the sign of the slip.
  EXPECT_DOUBLE_EQ(coulomb_projection_friction_n(1e-2, compliance, limit), limit);
  EXPECT_DOUBLE_EQ(coulomb_projection_friction_n(-1e-2, compliance, limit), -limit);
  EXPECT_GT(1e-2 - compliance * limit, 0.0);  // still slipping the same way
  EXPECT_DOUBLE_EQ(coulomb_projection_friction_n(1.0, compliance, 0.0), 0.0);
}

TEST(ErfImplicitFriction, SolvesTheImplicitEquation) {
  const double kappa = 3.6e6;
  const double compliance = 2e-5;
  const double limit = 8.0;
  for (double v_star : {-1e-3, -1.5e-4, -1e-6, 1e-9, 3e-7, 1e-4, 1.6e-4, 1.61e-4, 0.3}) {
    const double f = erf_implicit_friction_n(v_star, compliance, limit, kappa);
    const double v = v_star - compliance * f;
    EXPECT_NEAR(f, limit * std::erf(kappa * v), 1e-9 * limit) << v_star;
    EXPECT_LE(std::abs(f), limit);
    // Within 1e-6 relative (of the cone) of the Coulomb projection, as model_spec §10 states.
    EXPECT_NEAR(f, coulomb_projection_friction_n(v_star, compliance, limit), 2e-2 * limit) << v_star;
  }
  EXPECT_EQ(erf_implicit_friction_n(0.0, compliance, limit, kappa), 0.0);
}

TEST(ErfImplicitFriction, ApproachesProjectionForSteepLaw) {
  const double compliance = 2e-5;
  const double limit = 8.0;
  for (double v_star : {-1e-3, 5e-5, 1e-4, 2e-4}) {
    EXPECT_NEAR(erf_implicit_friction_n(v_star, compliance, limit, 3.6e12),
                coulomb_projection_friction_n(v_star, compliance, limit), 1e-6 * limit);
  }
}

}  // namespace
}  // namespace swum

namespace swum {
namespace {

// Jenkins element (tangential spring k_t in series with a Coulomb slider).
TEST(JenkinsElement, SticksElasticallyBelowTheConeAndSlidesAtIt) {
  const double kt = 2e8;
  const double limit_n = 0.35 * 20.0;  // mu_c F_N
  const double limit_m = limit_n / kt;
  // Stick: a small tip motion deflects the spring exactly by the motion (force k_t delta).
  double delta = jenkins_return_mapping_m(0.0, 1e-9, limit_m);
  EXPECT_DOUBLE_EQ(delta, 1e-9);
  EXPECT_DOUBLE_EQ(jenkins_force_n(kt, delta, limit_n), kt * 1e-9);
  EXPECT_LT(jenkins_force_n(kt, delta, limit_n), limit_n);
  // Slide: further motion saturates the force at mu_c F_N (the slider slips).
  for (int k = 0; k < 100; ++k) delta = jenkins_return_mapping_m(delta, 1e-9, limit_m);
  EXPECT_DOUBLE_EQ(delta, limit_m);
  EXPECT_DOUBLE_EQ(jenkins_force_n(kt, delta, limit_n), limit_n);
  // Reversal unloads elastically from the cone (no jump to -limit).
  delta = jenkins_return_mapping_m(delta, -1e-9, limit_m);
  EXPECT_NEAR(jenkins_force_n(kt, delta, limit_n), limit_n - kt * 1e-9, 1e-9);
  // Separation (F_N = 0): delta = 0 and no force.
  EXPECT_EQ(jenkins_return_mapping_m(delta, 3e-9, 0.0), 0.0);
  EXPECT_EQ(jenkins_force_n(kt, 1e-8, 0.0), 0.0);
}

TEST(JenkinsElement, ContinuousFormIsThePlayOperator) {
  const double lim = 4e-8;
  EXPECT_EQ(jenkins_deflection_rate_m_s(1e-8, lim, 0.0, 0.3), 0.3);     // stick: delta' = v_rel
  EXPECT_EQ(jenkins_deflection_rate_m_s(lim, lim, -0.01, 0.3), -0.01);  // slip: follows the cone
  EXPECT_EQ(jenkins_deflection_rate_m_s(lim, lim, 0.0, -0.3), -0.3);    // unloading: elastic
  EXPECT_EQ(jenkins_deflection_rate_m_s(-lim, lim, 0.02, -0.3), -0.02);
  EXPECT_EQ(jenkins_deflection_rate_m_s(0.0, 0.0, 0.0, 0.3), 0.0);  // separation
}

}  // namespace
}  // namespace swum
