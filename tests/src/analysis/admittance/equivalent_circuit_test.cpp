// The analytic BVD circuit: its motional elements from the modal constants (R_m N^2 = C,
// L_m N^2 = M, with N the stator's linear force per volt), the series resonance and the
// parallel resonance against where the susceptance of a branch with C0 crosses zero, and the two
// forms of the coupling factor.
#include "analysis/admittance/equivalent_circuit.h"

#include <gtest/gtest.h>

#include <cmath>

#include "admittance_test_support.h"
#include "model/motor_model.h"

namespace swum {
namespace {

TEST(EquivalentCircuit, MotionalElementsTimesTheForceFactorSquaredAreTheModalDampingAndMass) {
  const MotorParameters p = test::calibrated_parameters();
  const MotorModel model(mounted_parameters(p, Mounting::free));
  const ModalConstants& k = model.constants();
  const StatorForceCoefficients& s = model.coefficients().stator;
  for (DrivenPhase phase : {DrivenPhase::a, DrivenPhase::b}) {
    const bool a = phase == DrivenPhase::a;
    const double n_l1 = a ? s.l1.lin0_a : s.l1.lin0_b;
    const double n_b2 = a ? s.b2.lin0_a : s.b2.lin0_b;
    const EquivalentCircuit c = analytic_equivalent_circuit(model, phase);
    EXPECT_NEAR(c.branches[0].resistance_ohm * n_l1 * n_l1 / p.stator.damping_l1_n_s_m, 1.0, 1e-12);
    EXPECT_NEAR(c.branches[1].resistance_ohm * n_b2 * n_b2 / p.stator.damping_b2_n_s_m, 1.0, 1e-12);
    EXPECT_NEAR(c.branches[0].inductance_h * n_l1 * n_l1 / k.m1_kg, 1.0, 1e-12);
    EXPECT_NEAR(c.branches[1].inductance_h * n_b2 * n_b2 / k.m2_kg, 1.0, 1e-12);
    // The force factors of li2019.toml (docs/model.md): 0.1074 N/V for L1, 0.1254 for B2.
    EXPECT_NEAR(std::abs(n_l1), 0.1074, 0.0005);
    EXPECT_NEAR(std::abs(n_b2), 0.1254, 0.0005);
    EXPECT_DOUBLE_EQ(c.clamped_capacitance_f, p.stator.clamped_capacitance_nf * 1e-9);
  }
}

// The frequency above fs where B = Im Y of C0 with the one branch crosses zero, by bisection.
double susceptance_zero_above_hz(const MotionalBranch& b, double c0) {
  EquivalentCircuit c;
  c.clamped_capacitance_f = c0;
  c.branches[0] = b;
  c.branches[1] = {1e30, 1.0, 1.0};  // carries no current
  const double fs = series_resonance_hz(b);
  double low = fs * (1.0 + 1e-5), high = 1.01 * fs;  // B < 0 just above fs, > 0 well above
  EXPECT_LT(circuit_admittance_siemens(c, low).imag(), 0.0);
  EXPECT_GT(circuit_admittance_siemens(c, high).imag(), 0.0);
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (low + high);
    (circuit_admittance_siemens(c, mid).imag() < 0.0 ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

TEST(EquivalentCircuit, ParallelResonanceIsWhereTheSusceptanceOfALowLossBranchWithC0CrossesZero) {
  const MotionalBranch b{1.0, 0.8, 2e-11};  // Q = 2e5: the crossing is fp to within 1e-3 Hz
  const double c0 = 1e-8;
  const double fp = parallel_resonance_hz(b, c0);
  EXPECT_NEAR(susceptance_zero_above_hz(b, c0), fp, 1e-3);
  EXPECT_GT(fp - series_resonance_hz(b), 35.0);  // C_m/C0 = 0.002: fp - fs = 0.001 fs
  EXPECT_NEAR((fp * fp - std::pow(series_resonance_hz(b), 2)) / (fp * fp), coupling_factor_squared(b, c0), 1e-12);
}

TEST(EquivalentCircuit, AdmittanceIsOneOverRmPlusC0AtTheSeriesResonance) {
  EquivalentCircuit c;
  c.clamped_capacitance_f = 1e-8;
  c.branches[0] = {3000.0, 0.8, 2e-11};
  c.branches[1] = {1e12, 1.0, 1e-11};  // a branch that carries no current
  const double fs = series_resonance_hz(c.branches[0]);
  const std::complex<double> y = circuit_admittance_siemens(c, fs);
  EXPECT_NEAR(y.real(), 1.0 / 3000.0, 1e-9);
  EXPECT_NEAR(y.imag(), 2.0 * M_PI * fs * 1e-8, 1e-9);
}

}  // namespace
}  // namespace swum
