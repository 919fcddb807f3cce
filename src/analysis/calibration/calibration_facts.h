// `swum calibrate --facts` (docs/calibration.md): the model's base parameters fitted to a few
// facts (formats/facts_file.h), each with its tolerance, and optionally to a measured sweep at
// the same time. A peak frequency moves in steps and jumps across the fold as parameters
// change, so finite differences across it would mislead Levenberg-Marquardt: the fit is a
// derivative-free bounded search (NLopt's Subplex) of
//   cost = sum over facts of w_f miss_f^2 + sum over training values of (r_i / sigma)^2,
// miss_f = (distance of the fact's value outside its band) / tolerance (1000 tolerances when
// the model cannot produce the value), plus for a fact given as a target
// 0.01 x ((value - target) / tolerance)^2 (so that, among parameter sets where every fact
// holds, the search prefers margin to the edges of target +- tolerance). The free set is
// chosen as for sweeps (calibration.h, step 1), with the facts' rows in the Jacobian: a target
// is a measurement with sigma = its tolerance (the slope of its value / tolerance), a bare band
// only while it is active (missed at either end of the finite-difference step). A parameter whose
// standard error (from the same Jacobian at the optimum) is not below half its prior spread, or
// that ended on a bound, goes back to its prior. Facts that still fail are pushed one at a
// time (weight x100): reachable or not, and which facts then lose (their miss grows); between
// the first such pair (the pushed fact and the one that loses most), the front: the optimum as
// the pushed fact's weight grows 1, 3, 10, 30, 100.
#pragma once

#include <span>
#include <vector>

#include "analysis/calibration/calibration.h"
#include "formats/facts_file.h"
#include "model/motor_model.h"

namespace swum {

// The model's value of each fact (NaN when it has none: no forward motion, a divergence), all
// (model, fact) pairs in one parallel batch; result[model][fact].
[[nodiscard]] std::vector<std::vector<double>> evaluate_facts(std::span<const MotorParameters> models,
                                                              std::span<const Fact> facts, const ParallelFor& parallel);

// Distance of `value` outside the fact's band in tolerances (0 inside; 1000 for NaN).
[[nodiscard]] double fact_miss(const Fact& fact, double value);

// `measured` may be null (facts only). Throws std::invalid_argument as calibrate_to_measurements.
[[nodiscard]] CalibrationResult calibrate_to_facts(const MotorParameters& prior, std::span<const Fact> facts,
                                                   const MeasurementSet* measured, const CalibrationOptions& options,
                                                   const ParallelFor& parallel);

}  // namespace swum
