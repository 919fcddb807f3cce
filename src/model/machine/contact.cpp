#include "model/machine/contact.h"

#include <numbers>

namespace swum {

double erf_implicit_friction_n(double v_star, double compliance, double limit_n, double kappa) {
  if (limit_n <= 0.0 || v_star == 0.0) return 0.0;
  const double sign = v_star > 0.0 ? 1.0 : -1.0;
  const double vs = sign * v_star;          // solve for v >= 0 by symmetry
  const double cap = compliance * limit_n;  // C: largest velocity change friction can make
  const double slope0 = 2.0 / std::sqrt(std::numbers::pi) * kappa;
  // g(v) = v + C erf(kappa v) - vs: increasing, concave on v >= 0; both starts have g <= 0.
  const double v_linear = vs / (1.0 + cap * slope0);
  const double v_coulomb = vs > cap ? vs - cap : 0.0;
  double v = v_linear > v_coulomb ? v_linear : v_coulomb;
  for (int it = 0; it < 30; ++it) {
    const double z = kappa * v;
    const double g = v + cap * std::erf(z) - vs;
    const double dg = 1.0 + cap * slope0 * std::exp(-z * z);
    const double dv = -g / dg;
    v += dv;
    if (std::abs(dv) <= 1e-14 * vs) break;
  }
  return sign * (vs - v) / compliance;
}

}  // namespace swum
