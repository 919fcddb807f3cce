// The discovery step of the discrepancy workflow (docs/discrepancy.md, "Discovery"): when the
// library of effects names nothing, or leaves a structured residual, or names an effect that a
// change of the base model explains better, the smallest change of the base model that brings
// the held-out residual to the noise. Changes are searched over physical groups of base
// parameters (parameter_groups.h), singly and in pairs, screened and fitted by the library's
// own steps (candidate_fitting.h), chosen by the Schwarz criterion on the training points and
// accepted only by the held-out tests that name a library effect (held_out_test.h), at the
// workflow's level divided by the changes the step may try to name (Bonferroni). A library effect
// stays named unless a change beats it by the BIC margin and on the held-out points: when it is
// the truth, it wins.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "analysis/discrepancy/parameter_groups.h"
#include "analysis/fit/disagreement_map.h"
#include "analysis/fit/held_out_test.h"
#include "analysis/fit/parameter_fit.h"

namespace swum {

struct DiscoveryOptions {
  bool enabled = true;
  std::vector<std::string> groups;  // group names; empty = every group that applies to the config
  int fitted_singles = 3;           // the best screened groups that get a full fit
  bool pairs = true;                // pairs of the best three groups when one leaves a structured residual
};

// One fitted change of the base model: one or two groups.
struct GroupFit {
  std::vector<std::string> groups;  // names (parameter_groups.h)
  std::vector<GroupChange> changes;
  std::vector<std::string> units;              // "factor" or the shift's unit
  std::vector<std::vector<std::string>> keys;  // per group, the "section.key"s it changes
  std::vector<double> values;
  std::vector<double> standard_errors;
  std::vector<bool> at_bound;  // the fit stopped on the group's bound
  // The library's named effects fitted jointly with it (their values, in the order named);
  // empty for a change of the baseline alone.
  std::vector<double> effect_values;
  std::vector<double> effect_standard_errors;
  bool ok = false;
  double delta_bic = 0.0;  // against the baseline, training points, every fitted parameter counted
  double train_rms = 0.0;  // relative
  double held_out_rms = 0.0;
  MotorParameters parameters;
  Predictions predictions;
  std::vector<double> residuals;
};

struct GroupScreening {
  std::string name;
  std::string note;  // why not screened ("" when screened)
  double value = 0.0;
  double delta_bic = 0.0;  // screened, against the baseline
};

enum class DiscoveryOutcome {
  not_run,             // disabled
  nothing_to_explain,  // nothing named and the baseline's residual within the noise
  nothing,             // no change passes (the verdict says which test failed)
  alone,               // the library named nothing; a change of the base model explains it
  with_library,        // on top of the library's effects
  instead_of_library,  // a change of the base model explains what the library's effects did, better
  library_stands,      // the library's effects explain it at least as well
};

struct Discovery {
  DiscoveryOutcome outcome = DiscoveryOutcome::not_run;
  std::vector<GroupScreening> screened;  // on the baseline
  std::vector<GroupFit> fits;            // changes of the baseline, by delta BIC (best first)
  // Changes fitted jointly with the library's effects (screened on the library's model), by
  // delta BIC; only when the library named effects and left a structured residual.
  std::vector<GroupFit> with_library_fits;
  std::optional<std::size_t> chosen;  // index into fits (outcome alone or instead_of_library)
  // Fits within the BIC margin of the chosen one (or of the library's effects when they stand):
  // these points cannot tell them apart. Not tested on the held-out points, not in the
  // augmented config: listed so that a reader does not take the choice for a proof.
  std::vector<std::size_t> indistinguishable;
  // The same for with_library_fits, against its first (outcome with_library).
  std::vector<std::size_t> indistinguishable_with_library;
  double library_delta_bic = 0.0;  // the library's named effects against the baseline
  // The level of each held-out test of the step: the workflow's significance, divided by the
  // number of changes the step may try to name (Bonferroni: two when it may name one beside the
  // library's effects and then one instead of them). The session's false-naming rate is at most
  // the library's level plus this one (docs/discrepancy.md).
  double significance = 0.0;
  HeldOutEvidence held_out;         // the tested change against the model it changes
  HeldOutEvidence against_library;  // instead_of_library: the change against the library's model
  HeldOutEvidence against_change;   // with_library: the joint model against the change alone
  std::string verdict;
  // The library's rounds on the changed model named effects beside an accepted change (outcome
  // alone or instead_of_library): the change and those effects were refitted jointly, the fit
  // is with_library_fits[0].
  bool effects_after_change = false;
};

// The change the step named (nullptr: none): a fit of `fits` or of `with_library_fits`.
[[nodiscard]] const GroupFit* accepted_change(const Discovery& d);

// Throws std::invalid_argument for an unknown group, one named twice, or one that does not
// apply to `baseline` (saying why).
void validate_discovery_groups(const DiscoveryOptions& options, const MotorParameters& baseline);

struct DiscoverySettings {
  DiscoveryOptions options;
  double bic_margin = 10.0;
  double significance = 0.01;
  bool robust = true;
  int max_fit_iterations = 8;
  int screening_steps = 2;
  std::uint64_t split_seed = 2019;
  PredictionOptions prediction;
};

// The two models the step starts from: the baseline and what the library named on it.
struct DiscoveryStart {
  const MotorParameters* baseline = nullptr;
  const Predictions* baseline_predictions = nullptr;
  const MotorParameters* library = nullptr;  // = baseline when nothing was named
  const Predictions* library_predictions = nullptr;
  std::vector<std::string> library_effects;  // named, in order
  std::vector<double> library_values;
  // The library's effects leave a residual within the noise: only the question "does a change
  // of the base model explain it as well?" is asked (single groups whose screening comes within
  // the margin of the library; no pairs, no joint fit), which keeps the step cheap where the
  // library has done its work.
  bool library_explains = false;
};

// Throws std::invalid_argument for an unknown group name or one that does not apply.
[[nodiscard]] Discovery run_discovery(const DiscoveryStart& start, const MeasurementSet& set,
                                      const ResidualModel& model, std::span<const std::size_t> train,
                                      std::span<const std::size_t> test, const DiscoverySettings& settings,
                                      const ParallelFor& parallel, int& evaluation_counter);

// `change` refitted jointly with `effects` (at `effect_values`) from the baseline: one fit of
// the change and the effects the library's rounds named on the changed model.
[[nodiscard]] GroupFit refit_change_with_effects(const GroupFit& change, const std::vector<std::string>& effects,
                                                 const std::vector<double>& effect_values,
                                                 const MotorParameters& baseline,
                                                 const Predictions& baseline_predictions, const MeasurementSet& set,
                                                 const ResidualModel& model, std::span<const std::size_t> train,
                                                 std::span<const std::size_t> test, const DiscoverySettings& settings,
                                                 const ParallelFor& parallel, int& evaluation_counter);

// "stator_damping x1.41 +- 0.02 (stator.damping_l1_n_s_m, stator.damping_b2_n_s_m together)"
[[nodiscard]] std::string describe_group_fit(const GroupFit& fit);

}  // namespace swum
