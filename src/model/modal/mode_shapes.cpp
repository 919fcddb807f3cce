#include "model/modal/mode_shapes.h"

#include <cmath>
#include <numbers>

namespace swum {

double free_free_b2_root() {
  // f(x) = cos x cosh x - 1, f'(x) = cosh x (cos x tanh x - sin x); start near 5 pi/2.
  double x = 2.5 * std::numbers::pi;
  for (int k = 0; k < 50; ++k) {
    const double f = std::cos(x) * std::cosh(x) - 1.0;
    const double df = std::cosh(x) * (std::cos(x) * std::tanh(x) - std::sin(x));
    const double dx = f / df;
    x -= dx;
    if (std::abs(dx) < 1e-15 * x) break;
  }
  return x;
}

ModeShapes::ModeShapes(double length_m) : length_m_(length_m) {
  const double bl = free_free_b2_root();
  beta_ = bl / length_m;
  a2_ = (std::sin(bl) - std::sinh(bl)) / (std::cosh(bl) - std::cos(bl));
}

double ModeShapes::phi_l(double x) const { return std::cos(std::numbers::pi * x / length_m_); }

double ModeShapes::phi_l_d1(double x) const {
  const double k = std::numbers::pi / length_m_;
  return -k * std::sin(k * x);
}

double ModeShapes::phi_b(double x) const {
  const double bx = beta_ * x;
  return a2_ * (std::cos(bx) + std::cosh(bx)) + (std::sin(bx) + std::sinh(bx));
}

double ModeShapes::phi_b_d1(double x) const {
  const double bx = beta_ * x;
  return beta_ * (a2_ * (-std::sin(bx) + std::sinh(bx)) + (std::cos(bx) + std::cosh(bx)));
}

double ModeShapes::phi_b_d2(double x) const {
  const double bx = beta_ * x;
  return beta_ * beta_ * (a2_ * (-std::cos(bx) + std::cosh(bx)) + (-std::sin(bx) + std::sinh(bx)));
}

}  // namespace swum
