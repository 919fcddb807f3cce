#include "model/modal/quadrature.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <numeric>

namespace swum {
namespace {

TEST(GaussLegendre, WeightsSumToTwoAndExactForPolynomials) {
  for (int n : {1, 2, 5, 16, 400}) {
    const GaussLegendre gl(n);
    EXPECT_NEAR(std::accumulate(gl.weights().begin(), gl.weights().end(), 0.0), 2.0, 1e-13);
    // Degree 2n-1 is integrated exactly.
    const int d = 2 * n - 1;
    if (d <= 41) {
      const double exact = (std::pow(2.0, d + 1) - 0.0) / (d + 1);  // Int_0^2 x^d dx
      EXPECT_NEAR(gl.integrate([d](double x) { return std::pow(x, d); }, 0.0, 2.0), exact, 1e-12 * exact);
    }
  }
}

TEST(GaussLegendre, SmoothFunctionsToMachinePrecision) {
  const GaussLegendre gl(400);
  EXPECT_NEAR(gl.integrate([](double x) { return std::sin(x); }, 0.0, std::numbers::pi), 2.0, 1e-13);
  EXPECT_NEAR(gl.integrate([](double x) { return std::exp(x); }, 0.0, 1.0), std::numbers::e - 1.0, 1e-14);
}

// The nodes are found four at a time (the Newton chains overlap in the pipeline); each must be
// the node the plain one-at-a-time Newton iteration gives, to the bit.
TEST(GaussLegendre, InterleavedNewtonGivesTheNodesOfOneAtATime) {
  for (int n : {1, 2, 3, 5, 8, 9, 33, 400, 1001}) {
    const GaussLegendre gl(n);
    for (int i = 0; i < (n + 1) / 2; ++i) {
      double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
      auto legendre = [n](double y, double& p0, double& p1) {
        p0 = 1.0;
        p1 = y;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2.0 * k - 1.0) * y * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
      };
      double p0 = 0.0, p1 = 0.0;
      for (int it = 0; it < 100; ++it) {
        legendre(x, p0, p1);
        const double dx = p1 / (n * (x * p1 - p0) / (x * x - 1.0));
        x -= dx;
        if (std::abs(dx) < 1e-16) break;
      }
      legendre(x, p0, p1);
      const double dp = n * (x * p1 - p0) / (x * x - 1.0);
      const auto hi = static_cast<std::size_t>(n - 1 - i);
      ASSERT_EQ(gl.nodes()[hi], x) << "n = " << n << ", node " << i;
      ASSERT_EQ(gl.weights()[hi], 2.0 / ((1.0 - x * x) * dp * dp)) << "n = " << n << ", node " << i;
    }
  }
}

}  // namespace
}  // namespace swum
