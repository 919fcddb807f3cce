#include "integrators/semi_implicit_euler.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace swum {
namespace {

// x'' + 2 zeta w x' + w^2 x = 0; stiffness explicit, damping either explicit or implicit.
struct Oscillator {
  using Vector = std::array<double, 1>;
  double w = 2.0;
  double zeta = 0.05;
  bool implicit_damping = false;
  void explicit_acceleration(double, const Vector& q, const Vector& v, Vector& a) const {
    a[0] = -w * w * q[0] - (implicit_damping ? 0.0 : 2 * zeta * w * v[0]);
  }
  void implicit_velocity_correction(double, double dt, const Vector&, const Vector&, Vector& v_star) const {
    if (implicit_damping) v_star[0] /= 1.0 + dt * 2 * zeta * w;
  }
};

double exact(double t, double w, double zeta) {
  const double wd = w * std::sqrt(1 - zeta * zeta);
  return std::exp(-zeta * w * t) * (std::cos(wd * t) + zeta * w / wd * std::sin(wd * t));
}

double error_at(double dt, Oscillator sys) {
  Oscillator::Vector q{1.0};
  Oscillator::Vector v{-0.5 * dt * sys.w * sys.w};  // staggered start: v at t = dt/2... to O(dt^2)
  const int n = static_cast<int>(std::lround(5.0 / dt));
  for (int k = 0; k < n; ++k) semi_implicit_euler_step(sys, k * dt, dt, q, v);
  return std::abs(q[0] - exact(n * dt, sys.w, sys.zeta));
}

TEST(SemiImplicitEuler, DampedOscillatorConverges) {
  const Oscillator sys;
  const double e1 = error_at(1e-3, sys);
  const double e2 = error_at(5e-4, sys);
  EXPECT_LT(e1, 2e-3);
  const double order = std::log2(e1 / e2);
  EXPECT_GT(order, 0.9);  // first order (damping explicit), second for the undamped part
}

TEST(SemiImplicitEuler, ImplicitCorrectionIsStableForStiffDamping) {
  Oscillator sys;
  sys.zeta = 1e6;  // damping rate 4e6 1/s; explicit Euler needs dt < 2.5e-7
  sys.implicit_damping = true;
  Oscillator::Vector q{1.0};
  Oscillator::Vector v{0.0};
  for (int k = 0; k < 1000; ++k) semi_implicit_euler_step(sys, k * 1e-3, 1e-3, q, v);
  EXPECT_TRUE(std::isfinite(q[0]));
  EXPECT_LE(std::abs(q[0]), 1.0);
  EXPECT_GT(q[0], 0.99);  // overdamped: creeps, no oscillation
}

}  // namespace
}  // namespace swum
