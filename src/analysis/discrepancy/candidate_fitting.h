// The steps the discrepancy workflow takes on any candidate change of the model, whether an
// effect of the library (candidate_effects.h) or a group of base parameters (parameter_groups.h):
// the Schwarz criterion, the Cauchy cost, the screening of one free parameter per candidate
// (a probe, then reweighted Gauss-Newton / secant steps, every candidate of a step in one
// batch) and the full fit (parameter_fit.h) with its Cauchy refit. One implementation for both,
// so a library effect and a base-parameter change are judged by the same numbers.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "analysis/fit/held_out_test.h"
#include "analysis/fit/parameter_fit.h"

namespace swum {

[[nodiscard]] double sum_of_squares(std::span<const double> r, std::span<const std::size_t> slots);
[[nodiscard]] double rms_of(std::span<const double> r, std::span<const std::size_t> slots);

// Schwarz criterion difference for `added` extra parameters: n ln(SSE1/SSE0) + added ln n.
[[nodiscard]] double delta_bic(double sse_new, double sse_old, std::size_t n, int added);

// Cauchy cost sum a^2 ln(1 + r^2/a^2) over `slots` (parameter_fit.h); a = 0: the sum of squares.
[[nodiscard]] double cauchy_cost(std::span<const double> r, std::span<const std::size_t> slots, double a);

// One candidate as screened: its free value, and what the model leaves there.
struct Screened {
  double theta = 0.0;   // (value - origin) / scale of the candidate's free parameter
  double sse = 0.0;     // training sum of squares
  double robust = 0.0;  // Cauchy cost at the round's scale
  Predictions predictions;
  std::vector<double> residuals;
};

struct ScreeningSettings {
  int steps = 2;             // Gauss-Newton/secant steps after the probe
  double bic_margin = 10.0;  // screening goes on only for candidates that could pass it
  double scale = 0.0;        // Cauchy scale of the round
  // Candidates of one family (the two directions of one group of base parameters) share one of
  // the three follow-up places: only the family's best goes on. Empty: every candidate its own.
  std::vector<std::size_t> families;
  std::size_t follow_up = 3;  // candidates (families) that go on after each step
};

using BatchPredictor = std::function<std::vector<Predictions>(const std::vector<MotorParameters>&)>;

// Screens candidates[c] (std::nullopt: skipped) on top of `current` (whose predictions and
// residuals are given): a probe at theta = 1 (one scale), then `steps` reweighted Gauss-Newton
// steps of the Cauchy cost, continued only for the (at most `follow_up`, one per family) candidates
// whose predicted minimum passes the BIC margin. Returns the best point of each candidate (theta 0, the current
// model, for a skipped one or one that never improved).
[[nodiscard]] std::vector<Screened> screen_candidates(const MotorParameters& current,
                                                      const std::vector<std::optional<FreeParameter>>& candidates,
                                                      const Predictions& current_predictions,
                                                      const std::vector<double>& current_residuals,
                                                      const ResidualModel& model, std::span<const std::size_t> train,
                                                      const ScreeningSettings& settings, const BatchPredictor& predict);

// "delta BIC -725; held-out: 14 of 15 points better, p = 0.00012 (signed-rank ..., sign-flip ...);
// RMS gap 20 % -> 3 % (reduction 85 %, 90 % interval 70..92 %)": the evidence of a verdict.
[[nodiscard]] std::string describe_evidence(double delta_bic, const HeldOutEvidence& e);

// The full fit of the evaluator's free parameters from `start`: the Cauchy M-estimate at
// `round_scale` (0: least squares), then, when robust, the refit at the scale of what that fit
// leaves (robust_refit). The last free parameter is the one being tried.
[[nodiscard]] ParameterFit fit_candidate(const ParameterEvaluator& eval, const ResidualModel& model,
                                         std::span<const std::size_t> train, const std::vector<double>& start,
                                         const Predictions* start_predictions, double round_scale, bool robust,
                                         int max_iterations);

}  // namespace swum
