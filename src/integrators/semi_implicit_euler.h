// Semi-implicit (symplectic) Euler with an implicit velocity correction for stiff dissipative
// forces (model_spec §10, generalised). Knows nothing about motors.
//
//   v* = v + dt a_explicit(t, q, v)
//   v_new = system.implicit_velocity_correction(t, dt, q, v, v*)   (in place on v*)
//   q_new = q + dt v_new
#pragma once

#include <cstddef>

namespace swum {

template <typename S>
concept SplitSecondOrderSystem = requires(S& s, double t, double dt, const typename S::Vector& cq,
                                          typename S::Vector& out) {
  s.explicit_acceleration(t, cq, cq, out);
  s.implicit_velocity_correction(t, dt, cq, cq, out);
};

template <SplitSecondOrderSystem S>
inline void semi_implicit_euler_step(S& system, double t, double dt, typename S::Vector& q, typename S::Vector& v) {
  typename S::Vector a{};
  system.explicit_acceleration(t, q, v, a);
  typename S::Vector v_new{};
  for (std::size_t i = 0; i < v.size(); ++i) v_new[i] = v[i] + dt * a[i];
  system.implicit_velocity_correction(t, dt, q, v, v_new);
  for (std::size_t i = 0; i < q.size(); ++i) {
    v[i] = v_new[i];
    q[i] += dt * v_new[i];
  }
}

}  // namespace swum
