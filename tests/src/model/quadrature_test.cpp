#include "model/quadrature.h"

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

}  // namespace
}  // namespace swum
