// The BVD circuit fitted to the simulated admittance of the free stator at a small signal equals
// the one that follows analytically from the modal constants (issue 36), for both phases and both
// modes, from guesses read off the data (not from the analytic values).
#include "analysis/admittance/circuit_fit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <vector>

#include "admittance_test_support.h"
#include "analysis/admittance/equivalent_circuit.h"
#include "model/motor_model.h"

namespace swum {
namespace {

double relative(double value, double reference) { return std::abs(value / reference - 1.0); }

class SmallSignalFit : public ::testing::TestWithParam<DrivenPhase> {};

TEST_P(SmallSignalFit, EqualsTheAnalyticCircuitWithinOnePercent) {
  const MotorParameters p = test::calibrated_parameters();
  const DrivenPhase phase = GetParam();
  const MotorModel model(mounted_parameters(p, Mounting::free));
  const EquivalentCircuit analytic = analytic_equivalent_circuit(model, phase);
  const auto points = test::sweep(p, phase, Mounting::free, 1.0, test::frequency_grid(38000.0, 41000.0, 50.0));
  const CircuitFit fit = test::fit_as_the_cli(p, phase, Mounting::free, points);
  ASSERT_TRUE(fit.ok) << fit.failure;
  EXPECT_LT(relative(fit.circuit.clamped_capacitance_f, analytic.clamped_capacitance_f), 0.01);
  for (std::size_t i = 0; i < kCircuitModes; ++i) {
    const MotionalBranch& f = fit.circuit.branches[i];
    const MotionalBranch& a = analytic.branches[i];
    const MotionalBranch& s = fit.start.branches[i];
    SCOPED_TRACE(i == 0 ? "L1" : "B2");
    // The fit started from the data's guesses (which share the conductance peak between two
    // detuned branches), not from the analytic circuit, and ended on it, several times closer.
    const double start_off = std::max({relative(s.resistance_ohm, a.resistance_ohm),
                                       relative(s.inductance_h, a.inductance_h),
                                       relative(s.capacitance_f, a.capacitance_f)});
    const double fit_off = std::max({relative(f.resistance_ohm, a.resistance_ohm),
                                     relative(f.inductance_h, a.inductance_h),
                                     relative(f.capacitance_f, a.capacitance_f)});
    std::printf("%s: start %.4f off, fit %.5f off the analytic circuit\n", i == 0 ? "L1" : "B2", start_off, fit_off);
    EXPECT_LT(fit_off, 0.2 * start_off);
    EXPECT_LT(relative(f.resistance_ohm, a.resistance_ohm), 0.01) << f.resistance_ohm << " vs " << a.resistance_ohm;
    EXPECT_LT(relative(f.inductance_h, a.inductance_h), 0.01) << f.inductance_h << " vs " << a.inductance_h;
    EXPECT_LT(relative(f.capacitance_f, a.capacitance_f), 0.01) << f.capacitance_f << " vs " << a.capacitance_f;
    EXPECT_LT(std::abs(series_resonance_hz(f) - series_resonance_hz(a)), 5.0);
    // The standard errors are finite and small at a small signal.
    EXPECT_LT(fit.standard_error.branches[i].resistance_ohm, 0.01 * f.resistance_ohm);
  }
  EXPECT_LT(fit.rms_relative_residual, 1e-4);
}

INSTANTIATE_TEST_SUITE_P(BothPhases, SmallSignalFit, ::testing::Values(DrivenPhase::a, DrivenPhase::b),
                         [](const auto& info) { return std::string(driven_phase_name(info.param)); });

TEST(CircuitFit, TooFewPointsIsAFailureNotAThrow) {
  std::vector<AdmittancePoint> points(5);
  for (std::size_t k = 0; k < points.size(); ++k) {
    points[k].frequency_hz = 39000.0 + 100.0 * k;
    points[k].magnitude_siemens = 1e-3;
    points[k].susceptance_siemens = 1e-3;
  }
  const CircuitFit fit = fit_equivalent_circuit(points);
  EXPECT_FALSE(fit.ok);
  EXPECT_FALSE(fit.failure.empty());
}

// Two identical modes: the data fix their summed branch (1/R_m + 1/R_m) but not how it is shared,
// so J^T J is singular and every standard error is infinite, not the tiny one a pseudo-inverse
// gives.
TEST(CircuitFit, AnUndeterminedSplitHasInfiniteStandardErrors) {
  EquivalentCircuit truth;
  truth.clamped_capacitance_f = 1e-8;
  truth.branches[0] = {3381.0, 0.8105, 20.02e-12};
  truth.branches[1] = truth.branches[0];
  std::vector<AdmittancePoint> points;
  for (double f = 38000.0; f <= 41000.0; f += 100.0) {
    const std::complex<double> y = circuit_admittance_siemens(truth, f);
    AdmittancePoint p;
    p.frequency_hz = f;
    p.conductance_siemens = y.real();
    p.susceptance_siemens = y.imag();
    p.magnitude_siemens = std::abs(y);
    points.push_back(p);
  }
  const CircuitFit fit = fit_equivalent_circuit(points);
  ASSERT_TRUE(fit.ok) << fit.failure;
  EXPECT_LT(fit.rms_relative_residual, 1e-8);
  const double g = 1.0 / fit.circuit.branches[0].resistance_ohm + 1.0 / fit.circuit.branches[1].resistance_ohm;
  EXPECT_NEAR(g * 3381.0 / 2.0, 1.0, 1e-4);
  for (const MotionalBranch& e : fit.standard_error.branches) {
    EXPECT_TRUE(std::isinf(e.resistance_ohm)) << e.resistance_ohm;
    EXPECT_TRUE(std::isinf(e.inductance_h)) << e.inductance_h;
  }
}

}  // namespace
}  // namespace swum
