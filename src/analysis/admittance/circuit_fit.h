// The BVD circuit (equivalent_circuit.h) fitted to a measured Y(f) (admittance_measurement.h):
// non-linear least squares with Ceres (Levenberg-Marquardt) on the complex residual
// (Y_circuit - Y_measured)/|Y_measured| (relative weighting, real and imaginary part), over
// the logarithms of C0 and of each mode's motional R_m, L_m, C_m, started from guesses read off the data
// (C0 from the susceptance at the grid's ends; the motional branches from the conductance
// peak's height, position and width: one peak split into two detuned branches for modes that
// overlap, as L1 and B2 of the free stator 47 Hz apart, one branch per peak for separate ones)
// and never from the analytic circuit; the solve with the least cost over these starts is
// kept. Standard errors from the covariance at the optimum (ceres::Covariance, scaled by the
// residual variance); an element the data do not determine (a singular J^T J) gets an infinite
// error.
#pragma once

#include <array>
#include <span>
#include <string>

#include "analysis/admittance/admittance_measurement.h"
#include "analysis/admittance/equivalent_circuit.h"

namespace swum {

struct CircuitFitOptions {
  int max_iterations = 500;
  // Which fitted branch is which mode: the motional inductances L_m = M/N^2 in the order of
  // these (pass the analytic circuit's, analytic_equivalent_circuit; a mode's mass and force
  // factor do not depend on the mounting, its stiffness does, so the order holds in contact
  // too, where the order of the resonances flips). Not set (0): the branch with the smaller
  // inductance is mode 0 (L1), as on li2019.toml at every level tried, 1-400 V, free and
  // assembled.
  std::array<double, kCircuitModes> reference_inductance_h{};
};

struct CircuitFit {
  bool ok = false;
  std::string failure;                 // why not ok
  EquivalentCircuit circuit;           // fitted
  EquivalentCircuit standard_error;    // one standard error of each element (same units; inf: undetermined)
  EquivalentCircuit start;             // the guesses from the data
  double rms_relative_residual = 0.0;  // sqrt(mean of |Y_circuit - Y|^2/|Y|^2)
  int points = 0;
  int iterations = 0;
};

// The fit's unknowns (C0 and R_m, L_m, C_m per mode) and the fewest points it takes.
inline constexpr std::size_t kCircuitFitUnknowns = 1 + 3 * kCircuitModes;
inline constexpr std::size_t kCircuitFitMinimumPoints = kCircuitFitUnknowns + 1;

// Needs at least kCircuitFitMinimumPoints points with a finite, non-zero admittance that did
// not diverge.
[[nodiscard]] CircuitFit fit_equivalent_circuit(std::span<const AdmittancePoint> points,
                                                const CircuitFitOptions& options = {});

}  // namespace swum
