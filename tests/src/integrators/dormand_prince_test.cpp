#include "integrators/dormand_prince.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace swum {
namespace {

struct Oscillator {
  using Vector = std::array<double, 2>;
  double w = 3.0;
  double zeta = 0.1;
  void derivative(double, const Vector& x, Vector& dx) const {
    dx[0] = x[1];
    dx[1] = -w * w * x[0] - 2 * zeta * w * x[1];
  }
};

double exact(double t, double w, double zeta) {
  const double wd = w * std::sqrt(1 - zeta * zeta);
  return std::exp(-zeta * w * t) * (std::cos(wd * t) + zeta * w / wd * std::sin(wd * t));
}

TEST(DormandPrince, MeetsTightTolerance) {
  const Oscillator sys;
  Oscillator::Vector x{1.0, 0.0};
  DormandPrinceOptions<Oscillator::Vector> opt;
  opt.relative_tolerance = 1e-11;
  opt.absolute_tolerance = {1e-13, 1e-13};
  int calls = 0;
  const auto stats = integrate_dormand_prince(sys, 0.0, 10.0, x, opt, [&](double, const auto&) { ++calls; });
  ASSERT_TRUE(stats.ok);
  EXPECT_EQ(static_cast<std::uint64_t>(calls), stats.accepted);
  EXPECT_NEAR(x[0], exact(10.0, sys.w, sys.zeta), 1e-9);
}

TEST(DormandPrince, FifthOrderWithFixedSteps) {
  const Oscillator sys;
  auto error = [&](double h) {
    Oscillator::Vector x{1.0, 0.0};
    DormandPrinceOptions<Oscillator::Vector> opt;
    opt.relative_tolerance = 1e10;  // never reject
    opt.absolute_tolerance = {1e10, 1e10};
    opt.initial_step = h;
    opt.max_step = h;
    integrate_dormand_prince(sys, 0.0, 4.0, x, opt, [](double, const auto&) {});
    return std::abs(x[0] - exact(4.0, sys.w, sys.zeta));
  };
  const double order = std::log2(error(0.04) / error(0.02));
  EXPECT_GT(order, 4.5);
  EXPECT_LT(order, 5.8);
}

TEST(DormandPrince, ReportsFailureInsteadOfLooping) {
  struct Blowup {
    using Vector = std::array<double, 1>;
    void derivative(double, const Vector& x, Vector& dx) const { dx[0] = x[0] * x[0]; }
  };
  Blowup::Vector x{1.0};  // x = 1/(1-t): singular at t = 1
  DormandPrinceOptions<Blowup::Vector> opt;
  opt.absolute_tolerance = {1e-12};
  opt.max_steps = 100000;
  const auto stats = integrate_dormand_prince(Blowup{}, 0.0, 2.0, x, opt, [](double, const auto&) {});
  EXPECT_FALSE(stats.ok);
}

}  // namespace
}  // namespace swum
