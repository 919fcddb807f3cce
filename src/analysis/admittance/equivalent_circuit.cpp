#include "analysis/admittance/equivalent_circuit.h"

#include <cmath>
#include <numbers>

namespace swum {

namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;
}

double series_resonance_hz(const MotionalBranch& b) {
  return 1.0 / (kTwoPi * std::sqrt(b.inductance_h * b.capacitance_f));
}

double parallel_resonance_hz(const MotionalBranch& b, double c0) {
  return series_resonance_hz(b) * std::sqrt(1.0 + b.capacitance_f / c0);
}

double coupling_factor_squared(const MotionalBranch& b, double c0) { return b.capacitance_f / (c0 + b.capacitance_f); }

double quality_factor(const MotionalBranch& b) {
  return kTwoPi * series_resonance_hz(b) * b.inductance_h / b.resistance_ohm;
}

std::complex<double> circuit_admittance_siemens(const EquivalentCircuit& c, double frequency_hz) {
  const double w = kTwoPi * frequency_hz;
  std::complex<double> y{0.0, w * c.clamped_capacitance_f};
  for (const MotionalBranch& b : c.branches) {
    y += 1.0 / std::complex<double>{b.resistance_ohm, w * b.inductance_h - 1.0 / (w * b.capacitance_f)};
  }
  return y;
}

EquivalentCircuit analytic_equivalent_circuit(const MotorModel& model, DrivenPhase phase, Mounting mounting) {
  const ModalConstants& k = model.constants();
  const StatorForceCoefficients& s = model.coefficients().stator;
  const bool a = phase == DrivenPhase::a;
  const double n[kCircuitModes] = {a ? s.l1.lin0_a : s.l1.lin0_b, a ? s.b2.lin0_a : s.b2.lin0_b};
  const double m[kCircuitModes] = {k.m1_kg, k.m2_kg};
  const MotorCoefficients& mc = model.coefficients();
  const bool held = mounting == Mounting::assembled;
  const double kk[kCircuitModes] = {k.k1_n_m + (held ? mc.g_n * mc.contact_stiffness_n_m : 0.0),
                                    k.k2_n_m + (held ? mc.g_t * mc.g_tv * mc.tangential_stiffness_n_m : 0.0)};
  const double c[kCircuitModes] = {k.c1_n_s_m, k.c2_n_s_m};
  EquivalentCircuit out;
  out.clamped_capacitance_f = model.parameters().stator.clamped_capacitance_nf * 1e-9;
  for (std::size_t i = 0; i < kCircuitModes; ++i) {
    const double n2 = n[i] * n[i];
    out.branches[i] = {c[i] / n2, m[i] / n2, n2 / kk[i]};
  }
  return out;
}

}  // namespace swum
