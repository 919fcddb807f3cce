// The model-discrepancy workflow (docs/discrepancy.md): disagreement map of the baseline,
// screening and fitting of the candidate effects on a training split, scoring on held-out
// points and by BIC, naming the effect that explains the structured residual, and repeating
// with the winner added until no candidate improves both held-out error and BIC.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "analysis/discrepancy/candidate_effects.h"
#include "analysis/discrepancy/discovery.h"
#include "analysis/fit/disagreement_map.h"
#include "analysis/fit/held_out_test.h"
#include "analysis/measurements/measured_point_model.h"
#include "analysis/measurements/measurements.h"

namespace swum {

struct DiscrepancyOptions {
  PredictionOptions prediction;
  std::vector<std::string> candidates;  // effect names; empty = all of candidate_effects()
  // Held out: a quarter of the operating points (a point's repeats with it), but at least
  // min_held_out_points (never more than half), so the held-out tests have power on small
  // sessions while the training points keep the power of the screening and of later rounds
  // (docs/discrepancy.md, "Selection").
  double held_out_fraction = 0.25;
  int min_held_out_points = 12;
  std::uint64_t split_seed = 2019;
  double floor_fraction = 0.05;  // residual floor (ResidualModel)
  // A candidate is named only if both: its BIC on the training points is lower by more than
  // bic_margin (Kass-Raftery "very strong": 10), AND on the held-out points it predicts better
  // by the one-sided signed-rank and sign-flip tests of the per-point errors, Bonferroni-
  // combined, at this significance level (held_out_test.h).
  double bic_margin = 10.0;
  double significance = 0.01;
  // The named value is the Cauchy M-estimate started from the least-squares fit (parameter_fit.h).
  bool robust = true;
  int max_effects = 3;
  int max_fit_iterations = 8;
  int screening_steps = 2;  // Gauss-Newton/secant steps per candidate before the full fit
  // After the library: changes of the base model (discovery.h), by the same criteria.
  DiscoveryOptions discovery;
};

struct CandidateScore {
  std::string name;
  bool skipped = false;
  std::string note;           // why skipped
  double value = 0.0;         // screened value of the free parameter
  double train_rms = 0.0;     // relative
  double held_out_rms = 0.0;  // relative
  double delta_bic = 0.0;     // against the current model (negative = better)
};

struct NamedEffect {
  std::string name;
  std::string key;  // free parameter key in [effects.<name>]
  std::string unit;
  double value = 0.0;
  double standard_error = 0.0;
  double delta_bic = 0.0;
  HeldOutEvidence held_out;  // against the model before this effect was added
};

struct DiscrepancyRound {
  bool after_change = false;               // on the model with the discovery's change of the base model
  std::vector<CandidateScore> candidates;  // in candidate order
  std::optional<std::size_t> fitted;       // index of the fully fitted candidate
  bool accepted = false;
  HeldOutEvidence held_out;  // of the fitted candidate (when there is one)
  double fitted_delta_bic = 0.0;
  std::string verdict;  // named, or which criterion failed and by how much
};

struct QuantityGap {
  int count = 0;                                                                // held-out values
  double rms_before = 0.0, max_before = 0.0, rms_after = 0.0, max_after = 0.0;  // relative
};

struct DiscrepancyResult {
  DisagreementMap baseline_map;      // all points
  DisagreementMap augmented_map;     // all points
  std::vector<NamedEffect> effects;  // in the order found (the library's, as the model keeps them)
  // Named by the library's rounds but explained better by a change of the base model
  // (discovery.outcome = instead_of_library): not in the augmented model.
  std::vector<NamedEffect> superseded;
  Discovery discovery;
  std::vector<DiscrepancyRound> rounds;
  MotorParameters augmented;
  Predictions baseline_predictions;
  Predictions augmented_predictions;
  std::vector<bool> held_out;  // per row
  int held_out_points = 0;     // operating points held out
  int operating_points = 0;
  double rms_before = 0.0;  // held-out, relative, all quantities
  double rms_after = 0.0;
  std::array<QuantityGap, kQuantityCount> gaps{};
  std::string conclusion;
  int model_evaluations = 0;  // parameter sets evaluated at every point
};

// Throws std::invalid_argument for an unknown candidate or group name.
[[nodiscard]] DiscrepancyResult run_discrepancy(const MotorParameters& baseline, const MeasurementSet& measured,
                                                const DiscrepancyOptions& options, const ParallelFor& parallel);

}  // namespace swum
