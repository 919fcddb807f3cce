// Adaptive Dormand-Prince RK5(4) (FSAL, PI step control) for any first-order system
// `derivative(t, x, dxdt)`. The tight-tolerance reference solver; knows nothing about motors.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace swum {

template <typename S>
concept FirstOrderSystem = requires(const S& s, double t, const typename S::Vector& x, typename S::Vector& dx) {
  s.derivative(t, x, dx);
};

template <typename Vector>
struct DormandPrinceOptions {
  double relative_tolerance = 1e-9;
  Vector absolute_tolerance{};  // per component
  double initial_step = 1e-9;
  double max_step = std::numeric_limits<double>::infinity();
  double min_step = 1e-18;
  std::uint64_t max_steps = 100'000'000;
};

struct DormandPrinceStats {
  bool ok = true;
  std::uint64_t accepted = 0;
  std::uint64_t rejected = 0;
  std::uint64_t evaluations = 0;
  double last_step = 0.0;  // suggested next step (reuse for a continuation)
};

// Integrates from t0 to t1 in place; observer(t, x) is called after every accepted step.
// Returns ok = false (and stops) if the step falls below min_step, max_steps is exceeded or
// the state becomes non-finite.
template <FirstOrderSystem S, typename Observer>
DormandPrinceStats integrate_dormand_prince(const S& system, double t0, double t1, typename S::Vector& x,
                                            const DormandPrinceOptions<typename S::Vector>& opt, Observer&& observer) {
  using V = typename S::Vector;
  constexpr double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
  constexpr double a21 = 1.0 / 5;
  constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
  constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
  constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561, a54 = -212.0 / 729;
  constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176,
                   a65 = -5103.0 / 18656;
  constexpr double b1 = 35.0 / 384, b3 = 500.0 / 1113, b4 = 125.0 / 192, b5 = -2187.0 / 6784, b6 = 11.0 / 84;
  // error = 5th order - 4th order weights
  constexpr double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200, e6 = 22.0 / 525,
                   e7 = -1.0 / 40;

  DormandPrinceStats stats;
  const std::size_t n = x.size();
  V k1{}, k2{}, k3{}, k4{}, k5{}, k6{}, k7{}, y{}, x_new{};
  double t = t0;
  double h = std::min(opt.initial_step, opt.max_step);
  double previous_error = 1e-4;
  system.derivative(t, x, k1);
  ++stats.evaluations;
  while (t < t1) {
    if (stats.accepted + stats.rejected >= opt.max_steps || h < opt.min_step) {
      stats.ok = false;
      break;
    }
    bool last = false;
    if (t + h >= t1) {
      h = t1 - t;
      last = true;
    }
    for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + h * a21 * k1[i];
    system.derivative(t + c2 * h, y, k2);
    for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + h * (a31 * k1[i] + a32 * k2[i]);
    system.derivative(t + c3 * h, y, k3);
    for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + h * (a41 * k1[i] + a42 * k2[i] + a43 * k3[i]);
    system.derivative(t + c4 * h, y, k4);
    for (std::size_t i = 0; i < n; ++i) y[i] = x[i] + h * (a51 * k1[i] + a52 * k2[i] + a53 * k3[i] + a54 * k4[i]);
    system.derivative(t + c5 * h, y, k5);
    for (std::size_t i = 0; i < n; ++i)
      y[i] = x[i] + h * (a61 * k1[i] + a62 * k2[i] + a63 * k3[i] + a64 * k4[i] + a65 * k5[i]);
    system.derivative(t + h, y, k6);
    for (std::size_t i = 0; i < n; ++i)
      x_new[i] = x[i] + h * (b1 * k1[i] + b3 * k3[i] + b4 * k4[i] + b5 * k5[i] + b6 * k6[i]);
    system.derivative(t + h, x_new, k7);
    stats.evaluations += 6;
    double err = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double e = h * (e1 * k1[i] + e3 * k3[i] + e4 * k4[i] + e5 * k5[i] + e6 * k6[i] + e7 * k7[i]);
      const double scale = opt.absolute_tolerance[i] +
                           opt.relative_tolerance * std::max(std::abs(x[i]), std::abs(x_new[i]));
      const double r = e / scale;
      err = std::max(err, r * r);
    }
    err = std::sqrt(err);
    if (!std::isfinite(err)) {
      if (h <= opt.min_step) {
        stats.ok = false;
        break;
      }
      h *= 0.1;
      ++stats.rejected;
      continue;
    }
    if (err <= 1.0) {
      t = last ? t1 : t + h;
      x = x_new;
      k1 = k7;  // FSAL
      ++stats.accepted;
      observer(t, static_cast<const V&>(x));
      // PI controller (Hairer & Wanner): alpha = 0.7/5, beta = 0.4/5.
      const double e = std::max(err, 1e-10);
      double factor = 0.9 * std::pow(e, -0.14) * std::pow(previous_error, 0.08);
      factor = std::clamp(factor, 0.2, 5.0);
      previous_error = e;
      if (!last) h = std::min(h * factor, opt.max_step);
      stats.last_step = h;
    } else {
      h *= std::clamp(0.9 * std::pow(err, -0.2), 0.1, 0.9);
      ++stats.rejected;
    }
  }
  return stats;
}

}  // namespace swum
