// Free-free mode shapes of eq. (11) (model_spec §1.2) and their derivatives.
#pragma once

namespace swum {

// Second non-zero root of cos(x) cosh(x) = 1 (x = beta2 L = 7.853205 = 2.499753 pi),
// computed by Newton iteration.
[[nodiscard]] double free_free_b2_root();

// phiL(x) = cos(pi x/L) and phiB(x) = a2 (cos bx + cosh bx) + (sin bx + sinh bx), b = root/L,
// a2 = (sin bL - sinh bL)/(cosh bL - cos bL). Derivatives are with respect to x (1/m^k).
class ModeShapes {
 public:
  explicit ModeShapes(double length_m);

  [[nodiscard]] double length_m() const { return length_m_; }
  [[nodiscard]] double phi_l(double x) const;
  [[nodiscard]] double phi_l_d1(double x) const;
  [[nodiscard]] double phi_b(double x) const;
  [[nodiscard]] double phi_b_d1(double x) const;
  [[nodiscard]] double phi_b_d2(double x) const;
  [[nodiscard]] double b2_wavenumber_per_m() const { return beta_; }
  [[nodiscard]] double b2_a2() const { return a2_; }

 private:
  double length_m_;
  double beta_;
  double a2_;
};

}  // namespace swum
