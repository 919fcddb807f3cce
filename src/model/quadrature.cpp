#include "model/quadrature.h"

#include <cmath>
#include <numbers>

namespace swum {

GaussLegendre::GaussLegendre(int n) : nodes_(static_cast<std::size_t>(n)), weights_(nodes_.size()) {
  for (int i = 0; i < (n + 1) / 2; ++i) {
    // Tricomi initial guess, then Newton on P_n.
    double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0;
      double p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    // Recompute the derivative at the converged node.
    double p0 = 1.0;
    double p1 = x;
    for (int k = 2; k <= n; ++k) {
      const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    dp = n * (x * p1 - p0) / (x * x - 1.0);
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    const auto lo = static_cast<std::size_t>(i);
    const auto hi = static_cast<std::size_t>(n - 1 - i);
    nodes_[lo] = -x;
    nodes_[hi] = x;
    weights_[lo] = w;
    weights_[hi] = w;
  }
}

}  // namespace swum
