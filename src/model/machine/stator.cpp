#include "model/machine/stator.h"

namespace swum {

StatorForceCoefficients make_stator_force_coefficients(const ModalConstants& c, const StatorParameters& s) {
  StatorForceCoefficients out;
  auto fill = [&](ModeForceCoefficients& m, const std::array<ElectricalCoefficient, 5>& x) {
    m.lin0_a = x[0].group_a;
    m.lin0_b = x[0].group_b;
    m.sq0_a = s.e311_c_per_v_m * x[1].group_a;
    m.sq0_b = s.e311_c_per_v_m * x[1].group_b;
    m.lin1_a = s.e311_c_per_v_m * x[2].group_a;
    m.lin1_b = s.e311_c_per_v_m * x[2].group_b;
    m.sq1_a = s.e3111_c_per_v_m * x[3].group_a;
    m.sq1_b = s.e3111_c_per_v_m * x[3].group_b;
    m.lin2_a = s.e3111_c_per_v_m * x[4].group_a;
    m.lin2_b = s.e3111_c_per_v_m * x[4].group_b;
  };
  fill(out.l1, c.a);
  out.l1.k = c.k1_n_m;
  out.l1.k2 = s.c111_pa * c.alpha1;
  out.l1.k3 = s.c1111_pa * c.beta1_per_m;
  fill(out.b2, c.b);
  out.b2.k = c.k2_n_m;
  out.b2.k2 = 0.0;
  out.b2.k3 = s.c1111_pa * c.beta2_per_m;
  return out;
}

PairedForceCoefficients make_paired_force_coefficients(const StatorForceCoefficients& c) {
  PairedForceCoefficients p;
  const auto& a = c.l1;
  const auto& b = c.b2;
  p.lin0_a = DoublePair{a.lin0_a, b.lin0_a};
  p.lin0_b = DoublePair{a.lin0_b, b.lin0_b};
  p.sq0_a = DoublePair{a.sq0_a, b.sq0_a};
  p.sq0_b = DoublePair{a.sq0_b, b.sq0_b};
  p.lin1_a = DoublePair{a.lin1_a, b.lin1_a};
  p.lin1_b = DoublePair{a.lin1_b, b.lin1_b};
  p.sq1_a = DoublePair{a.sq1_a, b.sq1_a};
  p.sq1_b = DoublePair{a.sq1_b, b.sq1_b};
  p.lin2_a = DoublePair{a.lin2_a, b.lin2_a};
  p.lin2_b = DoublePair{a.lin2_b, b.lin2_b};
  p.k = DoublePair{a.k, b.k};
  p.k2 = DoublePair{a.k2, b.k2};
  p.k3 = DoublePair{a.k3, b.k3};
  return p;
}

}  // namespace swum
