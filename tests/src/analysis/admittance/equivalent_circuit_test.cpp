// The analytic BVD circuit: its elements from the modal constants (R1 = C/N^2, L1 = M/N^2,
// C1 = N^2/K), the series resonance equal to the mode's natural frequency, and the two forms of
// the coupling factor.
#include "analysis/admittance/equivalent_circuit.h"

#include <gtest/gtest.h>

#include <cmath>

#include "admittance_test_support.h"

namespace swum {
namespace {

TEST(EquivalentCircuit, SeriesResonancesAreTheNaturalFrequenciesAndQIsTheModes) {
  const MotorModel model(mounted_parameters(test::calibrated_motor(), Mounting::free));
  const ModalConstants& k = model.constants();
  for (DrivenPhase phase : {DrivenPhase::a, DrivenPhase::b}) {
    const EquivalentCircuit c = analytic_equivalent_circuit(model, phase);
    EXPECT_NEAR(series_resonance_hz(c.branches[0]), k.f_l1_hz, 1e-6 * k.f_l1_hz);
    EXPECT_NEAR(series_resonance_hz(c.branches[1]), k.f_b2_hz, 1e-6 * k.f_b2_hz);
    EXPECT_NEAR(quality_factor(c.branches[0]), std::sqrt(k.k1_n_m * k.m1_kg) / k.c1_n_s_m, 1e-6 * 1000.0);
    EXPECT_DOUBLE_EQ(c.clamped_capacitance_f, model.parameters().stator.clamped_capacitance_nf * 1e-9);
  }
}

TEST(EquivalentCircuit, CouplingFactorFromTheResonancesEqualsTheCapacitanceRatio) {
  const MotionalBranch b{3000.0, 0.8, 2e-11};
  const double c0 = 1e-8;
  const double fs = series_resonance_hz(b);
  const double fp = parallel_resonance_hz(b, c0);
  EXPECT_GT(fp, fs);
  EXPECT_NEAR((fp * fp - fs * fs) / (fp * fp), coupling_factor_squared(b, c0), 1e-12);
}

TEST(EquivalentCircuit, AdmittanceIsRealOneOverR1PlusC0AtTheSeriesResonance) {
  EquivalentCircuit c;
  c.clamped_capacitance_f = 1e-8;
  c.branches[0] = {3000.0, 0.8, 2e-11};
  c.branches[1] = {1e12, 1.0, 1e-11};  // a branch that carries no current
  const double fs = series_resonance_hz(c.branches[0]);
  const std::complex<double> y = circuit_admittance_s(c, fs);
  EXPECT_NEAR(y.real(), 1.0 / 3000.0, 1e-9);
  EXPECT_NEAR(y.imag(), 2.0 * M_PI * fs * 1e-8, 1e-9);
}

}  // namespace
}  // namespace swum
