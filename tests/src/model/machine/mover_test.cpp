#include "model/machine/mover.h"

#include <gtest/gtest.h>

#include <cmath>

namespace swum {
namespace {

TEST(SmoothSign, TanhAndExactSign) {
  for (double v : {-3e-4, -1e-5, 0.0, 2e-5, 1e-4, 5e-3}) {
    EXPECT_NEAR(smooth_sign(v, 1e-4), std::tanh(v / 1e-4), 1e-4) << v;
  }
  double previous = -1.0;
  for (double x = -6.0; x <= 6.0; x += 1e-3) {  // monotone and bounded
    const double y = smooth_sign(x, 1.0);
    EXPECT_GE(y, previous) << x;
    EXPECT_LE(std::abs(y), 1.0);
    previous = y;
  }
  EXPECT_EQ(smooth_sign(-1e-9, 0.0), -1.0);
  EXPECT_EQ(smooth_sign(0.0, 0.0), 0.0);
}

TEST(GuideFriction, CoulombWhileMovingOpposesMotion) {
  const auto g = make_guide_friction(0.04, 9.81 * 0.2, 1e-4);
  // Moving forward fast, no load: the instantaneous |F_T| > f_max -> F_f = -f_max.
  const double ff = guide_friction_n(g, 5.0, 24.8, 0.0, 0.2);
  EXPECT_NEAR(ff, -0.04 * (24.8 + 1.962), 1e-12);
  EXPECT_GT(guide_friction_n(g, 5.0, 24.8, 0.0, -0.2), 0.0);  // moving backward: pushes forward
}

TEST(GuideFriction, StuckBranchCancelsDriveAndLoad) {
  const auto g = make_guide_friction(0.04, 9.81 * 0.2, 1e-4);
  // Small drive force below the breakaway level with a load: F_f = F_load - F_T.
  const double load = 0.5;
  const double ft = 0.8;
  const double ff = guide_friction_n(g, ft, 24.8, load, 0.2);
  EXPECT_DOUBLE_EQ(ff, load - ft);
  // Net force on the mover is then -c v_m only (eq. 25).
  EXPECT_NEAR(mover_acceleration_m_s2(1 / 0.2, 1.3, ft, ff, load, 0.1), -1.3 * 0.1 / 0.2, 1e-12);
}

}  // namespace
}  // namespace swum

namespace swum {
namespace {

TEST(CoulombGuide, StuckInsideTheCapSlidesOutside) {
  const double cap = 1e-4;
  EXPECT_EQ(coulomb_guide_velocity_m_s(0.9e-4, cap), 0.0);
  EXPECT_EQ(coulomb_guide_velocity_m_s(-1e-4, cap), 0.0);
  EXPECT_DOUBLE_EQ(coulomb_guide_velocity_m_s(3e-4, cap), 2e-4);
  EXPECT_DOUBLE_EQ(coulomb_guide_velocity_m_s(-3e-4, cap), -2e-4);
  const auto g = make_guide_friction(0.04, 9.81 * 0.2, 1e-4);
  EXPECT_NEAR(coulomb_guide_friction_n(g, 24.8, 0.1), -0.04 * (24.8 + 1.962), 1e-9);
  EXPECT_EQ(coulomb_guide_friction_n(g, 24.8, 0.0), 0.0);
}

}  // namespace
}  // namespace swum
