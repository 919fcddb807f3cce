// `swum calibrate` on measured sweeps (docs/calibration.md): base parameters of the model
// fitted to measured speed (and tip amplitudes, where present) over frequency, voltage and
// load, as `swum sweep` writes them.
//  1. The free set: the candidates (calibration_candidates.h) the design can determine, taken
//     in their order of preference (the parameters most likely to differ between motors of one
//     design first; --candidates gives another order). From the Jacobian J at the prior
//     (forward differences, one batch; rows divided by the data's noise estimate sigma), a
//     candidate joins while every selected parameter's expected standard error
//     sqrt(diag (J'J)^-1) (the Fisher information of the design) stays below half its prior
//     spread, up to max_free. The rest are reported as insensitive, collinear (with whom) or
//     left out of a full set, and held at their priors. (Which parameters explain the misfit
//     cannot be judged from J at the prior: across a resonance peak the residual is far from
//     linear in the parameters.)
//  2. The fit: bounded Levenberg-Marquardt (parameter_fit.h) on the training points from the
//     prior and seeded random starts; the best is refitted with the Cauchy loss.
//  3. The verdict: a parameter whose standard error is not below half its prior spread is not
//     identifiable: it goes back to its prior and the others are refitted (a round per
//     parameter dropped), so nothing is fitted to noise.
//  4. Held-out points score prior and fit; correlations of the estimates are reported.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "analysis/fit/disagreement_map.h"
#include "analysis/fit/held_out_test.h"
#include "analysis/measurements/measured_point_model.h"
#include "analysis/measurements/measurements.h"
#include "model/parameters.h"

namespace swum {

struct CalibrationOptions {
  PredictionOptions prediction;
  // Parameters to fit ("section.key"); empty: chosen from the Fisher information among
  // `candidates` (empty: every applicable candidate).
  std::vector<std::string> free;
  std::vector<std::string> candidates;
  int max_free = 6;
  // Identifiable: standard error < this x the prior spread (the data must at least halve what
  // was known before; docs/calibration.md).
  double max_spread_fraction = 0.5;
  // The noise used for the expected standard errors of the selection: the data's estimate
  // (disagreement_map.h), but not below this (relative; the measurement protocol itself
  // differs from a device's by ~1 %).
  double min_noise = 0.01;
  int starts = 3;  // the prior, then seeded random starts within +-1.5 spreads
  std::uint64_t seed = 2019;
  int max_iterations = 20;
  bool robust = true;  // refit the best start with the Cauchy loss (parameter_fit.h)
  HeldOutSplit split;
  double floor_fraction = 0.05;  // residual floor (ResidualModel)
  // With facts (calibration_facts.h): the derivative-free search's budget of cost evaluations
  // per fit, and whether failing facts are pushed one by one and fronts traced.
  int max_evaluations = 300;
  bool trade_offs = true;
};

struct CandidateInformation {
  std::string name;
  double expected_standard_error = 0.0;  // alone, in units of its spread
  bool selected = false;
  std::string reason;  // why not selected ("" when selected)
};

struct CalibratedParameter {
  std::string name;  // "section.key"
  std::string unit;
  double prior = 0.0;
  double spread = 0.0;
  double value = 0.0;           // fitted when identifiable, else the prior
  double standard_error = 0.0;  // +inf when not identifiable
  double lower = 0.0, upper = 0.0;
  bool identifiable = false;
  bool at_bound = false;  // the fit stopped on a bound
  std::string reason;     // why not identifiable
};

// A fact (formats/facts_file.h) before and after the calibration.
struct FactOutcome {
  std::string id;
  std::string unit;
  double min = 0.0, max = 0.0;  // the band it must lie in
  double prior_value = 0.0;     // NaN: the model could not produce it (no forward motion, a divergence)
  double value = 0.0;
  double explored_value = 0.0;  // at the first fit, every free parameter moving
  bool holds_prior = false;
  bool holds = false;
  bool holds_explored = false;
};

// What pushing one fact that failed the joint fit to hold does to the others (weight x100).
struct FactReach {
  std::string id;
  bool reachable = false;           // it holds then
  double value = 0.0;               // its value then
  std::vector<std::string> breaks;  // facts that lose then: their miss grows (held and fail, or fail by more)
};

// The front between two conflicting facts: the optimum as the weight of `first` grows.
struct FactFront {
  std::string first, second;
  std::vector<double> weights;       // of `first` (the others weigh 1)
  std::vector<double> first_values;  // at each weight
  std::vector<double> second_values;
  std::vector<double> first_misses;  // in tolerances outside the band (0: holds)
  std::vector<double> second_misses;
};

struct CalibrationResult {
  std::vector<CandidateInformation> selection;    // empty when the free set was given
  std::vector<CalibratedParameter> parameters;    // the free set, identifiable or not
  std::vector<std::vector<double>> correlations;  // of the identifiable ones, in their order
  MotorParameters fitted;
  Predictions prior_predictions, fitted_predictions;
  std::vector<bool> held_out;  // per row
  int held_out_points = 0, operating_points = 0;
  double noise = 0.0;  // relative, estimated from the data
  std::string noise_source;
  double train_rms_prior = 0.0, train_rms = 0.0;  // relative
  double held_out_rms_prior = 0.0, held_out_rms = 0.0;
  HeldOutEvidence held_out_evidence;  // fit against prior on the held-out points
  std::vector<FactOutcome> facts;     // with --facts
  // With facts: the first fit, before parameters the facts do not determine went back to their
  // priors (what the facts allow, as against what they determine).
  std::vector<std::pair<std::string, double>> explored;
  std::vector<FactReach> reach;  // the facts that failed the joint fit
  std::vector<FactFront> fronts;
  int rounds = 0;
  int starts_run = 0;
  int model_evaluations = 0;  // parameter sets evaluated at every point
  std::string conclusion;
};

// Throws std::invalid_argument for an unknown or inapplicable parameter name, a free set
// as large as the number of training values or larger, or an empty candidate list.
[[nodiscard]] CalibrationResult calibrate_to_measurements(const MotorParameters& prior, const MeasurementSet& measured,
                                                          const CalibrationOptions& options,
                                                          const ParallelFor& parallel);

}  // namespace swum
