// The BVD circuit (equivalent_circuit.h) fitted to a measured Y(f) (admittance_measurement.h):
// non-linear least squares with Ceres (Levenberg-Marquardt) on the complex residual
// (Y_circuit - Y_measured)/|Y_measured| (relative weighting, real and imaginary part), over
// the logarithms of C0 and of each mode's R1, L1, C1, started from guesses read off the data
// (C0 from the susceptance at the grid's ends, the conductance peak's height, position and
// width for the motional branches) and never from the analytic circuit; standard errors from
// the covariance at the optimum (ceres::Covariance, scaled by the residual variance).
#pragma once

#include <array>
#include <span>
#include <string>

#include "analysis/admittance/admittance_measurement.h"
#include "analysis/admittance/equivalent_circuit.h"

namespace swum {

struct CircuitFitOptions {
  int max_iterations = 500;
  // Series resonances of the two modes in the model's order (the guesses' labelling only: the
  // fitted branch with the higher fs is named the mode with the higher natural frequency).
  bool first_mode_higher = true;
};

struct CircuitFit {
  bool ok = false;
  std::string failure;                 // why not ok
  EquivalentCircuit circuit;           // fitted
  EquivalentCircuit standard_error;    // one standard error of each element (same units)
  EquivalentCircuit start;             // the guesses from the data
  double rms_relative_residual = 0.0;  // sqrt(mean of |Y_circuit - Y|^2/|Y|^2)
  int points = 0;
  int iterations = 0;
};

// Needs at least 8 points (7 unknowns) with a finite, non-zero admittance.
[[nodiscard]] CircuitFit fit_equivalent_circuit(std::span<const AdmittancePoint> points,
                                                const CircuitFitOptions& options = {});

}  // namespace swum
