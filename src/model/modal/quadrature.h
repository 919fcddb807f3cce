// Gauss-Legendre quadrature (model_spec §1.5: modal and electrical integrals).
#pragma once

#include <vector>

namespace swum {

class GaussLegendre {
 public:
  // n nodes on [-1, 1] (Newton on P_n, Golub-Welsch accuracy ~1e-15 for n <= a few 1000).
  explicit GaussLegendre(int n);

  // Integral of f over [a, b].
  template <typename F>
  [[nodiscard]] double integrate(F&& f, double a, double b) const {
    const double half = 0.5 * (b - a);
    const double mid = 0.5 * (b + a);
    double sum = 0.0;
    for (std::size_t k = 0; k < nodes_.size(); ++k) sum += weights_[k] * f(mid + half * nodes_[k]);
    return half * sum;
  }

  [[nodiscard]] const std::vector<double>& nodes() const { return nodes_; }
  [[nodiscard]] const std::vector<double>& weights() const { return weights_; }

 private:
  std::vector<double> nodes_;
  std::vector<double> weights_;
};

}  // namespace swum
