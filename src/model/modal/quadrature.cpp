#include "model/modal/quadrature.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace swum {

namespace {

// Nodes are found kLanes at a time: each node's Newton iteration is a chain of ~n dependent
// divisions (the three-term recurrence), so one node at a time leaves the divider idle most of
// the time (~2.5 ms of every process start at n = 400). Interleaved, the chains overlap. Every
// lane runs exactly the operations it ran alone, so the nodes and weights are the same bits.
constexpr int kLanes = 4;

// P_n(x) into p1 and P_n-1(x) into p0 for every lane.
void legendre(int n, const double (&x)[kLanes], double (&p0)[kLanes], double (&p1)[kLanes]) {
  for (int j = 0; j < kLanes; ++j) {
    p0[j] = 1.0;
    p1[j] = x[j];
  }
  for (int k = 2; k <= n; ++k) {
    for (int j = 0; j < kLanes; ++j) {
      const double p2 = ((2.0 * k - 1.0) * x[j] * p1[j] - (k - 1.0) * p0[j]) / k;
      p0[j] = p1[j];
      p1[j] = p2;
    }
  }
}

}  // namespace

GaussLegendre::GaussLegendre(int n) : nodes_(static_cast<std::size_t>(n)), weights_(nodes_.size()) {
  const int half = (n + 1) / 2;
  for (int first = 0; first < half; first += kLanes) {
    const int lanes = std::min(kLanes, half - first);
    double x[kLanes];
    bool active[kLanes];
    int iterations[kLanes];
    for (int j = 0; j < kLanes; ++j) {
      // Tricomi initial guess (padding lanes repeat the last node and are discarded).
      const int i = first + std::min(j, lanes - 1);
      x[j] = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
      active[j] = j < lanes;
      iterations[j] = 0;
    }
    double p0[kLanes], p1[kLanes];
    // Newton on P_n, per lane until |dx| < 1e-16 or 100 iterations.
    while (std::any_of(active, active + kLanes, [](bool a) { return a; })) {
      legendre(n, x, p0, p1);
      for (int j = 0; j < kLanes; ++j) {
        if (!active[j]) continue;
        const double dp = n * (x[j] * p1[j] - p0[j]) / (x[j] * x[j] - 1.0);
        const double dx = p1[j] / dp;
        x[j] -= dx;
        if (std::abs(dx) < 1e-16 || ++iterations[j] == 100) active[j] = false;
      }
    }
    // The derivative at the converged nodes, for the weights.
    legendre(n, x, p0, p1);
    for (int j = 0; j < lanes; ++j) {
      const double dp = n * (x[j] * p1[j] - p0[j]) / (x[j] * x[j] - 1.0);
      const double w = 2.0 / ((1.0 - x[j] * x[j]) * dp * dp);
      const auto lo = static_cast<std::size_t>(first + j);
      const auto hi = static_cast<std::size_t>(n - 1 - first - j);
      nodes_[lo] = -x[j];
      nodes_[hi] = x[j];
      weights_[lo] = w;
      weights_[hi] = w;
    }
  }
}

}  // namespace swum
