// The discovery step (src/analysis/discrepancy/discovery.h, docs/discrepancy.md "Discovery") on
// sessions with a change outside the library hidden in them: a covering design of five changes
// of the base model (stator damping, a modal frequency shift, contact stiffness, mover mass, a
// non-linear constant) over sessions through the peak and above it, spot and swept, speed only
// and all quantities, 30-200 points, with a bench's noise. And the other direction: a library
// effect that is the truth stays named as itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <random>
#include <string>

#include "../discrepancy_test_support.h"
#include "../session_designs.h"
#include "analysis/discrepancy/discrepancy.h"
#include "analysis/discrepancy/parameter_groups.h"

namespace swum {
namespace {

struct HiddenChange {
  const char* group;
  double value;  // factor or shift
  test::Design design;
};

void PrintTo(const HiddenChange& c, std::ostream* os) { *os << c.group << " " << c.value << " on " << c.design.name; }

// Every group of the done-when once; every session feature level at least once.
const HiddenChange kChanges[] = {
    {"stator_damping", 1.4, {"through_shuffled_60_spot", true, true, 60, 1, false, false}},
    {"modal_frequencies", 120.0, {"through_ordered_60_sweeps", true, false, 60, 1, true, false}},
    {"contact_stiffness", 0.6, {"through_ordered_200_sweeps_speed", true, false, 200, 1, true, true}},
    {"mover_mass", 4.0, {"above_shuffled_30_repeats", false, true, 30, 2, false, false}},
    {"elastic_nonlinearity", 0.3, {"above_ordered_60_spot", false, false, 60, 1, false, false}},
};

class HiddenBaseChange : public ::testing::TestWithParam<HiddenChange> {};

TEST_P(HiddenBaseChange, RightGroupNamedWithinThreeStandardErrorsAndGapClosed) {
  const HiddenChange& c = GetParam();
  const ParameterGroup* group = find_parameter_group(c.group);
  ASSERT_NE(group, nullptr);
  const MotorParameters baseline = test::calibrated_motor();
  MotorParameters hidden = baseline;
  group_free_parameter(*group, baseline).apply(hidden, c.value);
  std::uint64_t seed = 1469598103934665603ULL;
  for (const char* ch = c.design.name; *ch != 0; ++ch)
    seed = (seed ^ static_cast<unsigned char>(*ch)) * 1099511628211ULL;
  const std::vector<Measurement> points = test::design_points(c.design, seed);
  const MeasurementSet data = synthesize_measurements(hidden, points, test::bench_noise(c.design, seed + 1),
                                                      test::two_thread_for);
  const MeasurementSet clean = test::clean_readings(hidden, points, c.design);

  const DiscrepancyResult r = run_discrepancy(baseline, data, {}, test::two_thread_for);
  std::string trace = "\n  conclusion: " + r.conclusion + "\n  discovery: " + r.discovery.verdict;
  for (const GroupFit& f : r.discovery.fits) trace += "\n    " + describe_group_fit(f);
  for (const GroupFit& f : r.discovery.with_library_fits) trace += "\n    beside: " + describe_group_fit(f);
  const Discovery& d = r.discovery;
  ASSERT_TRUE(d.outcome == DiscoveryOutcome::alone || d.outcome == DiscoveryOutcome::instead_of_library) << trace;
  EXPECT_TRUE(r.effects.empty()) << "a library effect named beside it" << trace;
  const GroupFit* found = &d.fits[*d.chosen];
  ASSERT_EQ(found->groups.size(), 1u) << trace;
  EXPECT_EQ(found->groups[0], c.group) << trace;
  if (found->groups[0] == c.group) {
    const double se = found->standard_errors[0];
    ASSERT_TRUE(std::isfinite(se) && se > 0.0) << "standard error " << se << trace;
    EXPECT_NEAR(found->values[0], c.value, 3.0 * se) << trace;
    EXPECT_FALSE(found->at_bound[0]) << trace;
  }
  const double before = test::held_out_gap_to_truth(data, clean, r.baseline_predictions, r.held_out);
  const double after = test::held_out_gap_to_truth(data, clean, r.augmented_predictions, r.held_out);
  EXPECT_LE(after, 0.3 * before) << "held-out gap to the truth " << before << " -> " << after << trace;
  RecordProperty("value", std::to_string(found->values[0]));
  RecordProperty("standard_error", std::to_string(found->standard_errors[0]));
  RecordProperty("gap_before", std::to_string(before));
  RecordProperty("gap_after", std::to_string(after));
}

INSTANTIATE_TEST_SUITE_P(Designs, HiddenBaseChange, ::testing::ValuesIn(kChanges),
                         [](const auto& info) { return std::string(info.param.group) + "_" + info.param.design.name; });

// The other direction: a library effect that is the truth stays named as itself, not as a change
// of the base model, on sessions where groups of base parameters can mimic part of it (damping
// takes droop's amplitude loss near the peak; contact stiffness and modal frequencies move the
// stiffened resonance as the preload does).
struct LibraryTruth {
  const char* effect;
  double value;
  test::Design design;
};

void PrintTo(const LibraryTruth& c, std::ostream* os) { *os << c.effect << " on " << c.design.name; }

const LibraryTruth kLibraryTruths[] = {
    {"amplifier_droop", 100.0, {"through_shuffled_60_spot", true, true, 60, 1, false, false}},
    {"preload", 0.8, {"through_ordered_60_sweeps", true, false, 60, 1, true, false}},
    // The two closest imitations: the mover mass acts through the guide's normal force, and the
    // elastic and electroelastic groups are halves of the library's electroelastic scale.
    {"guide_friction", 0.05, {"above_ordered_60_repeats_speed", false, false, 60, 2, false, true}},
    {"electroelastic", 0.6, {"through_shuffled_60_spot", true, true, 60, 1, false, false}},
};

class LibraryEffectTruth : public ::testing::TestWithParam<LibraryTruth> {};

TEST_P(LibraryEffectTruth, IsNamedAsItselfNotAsABaseChange) {
  const LibraryTruth& c = GetParam();
  const MotorParameters baseline = test::calibrated_motor();
  MotorParameters hidden = baseline;
  enable_effect(hidden, *find_candidate_effect(c.effect), c.value);
  const std::vector<Measurement> points = test::design_points(c.design, 77);
  const MeasurementSet data = synthesize_measurements(hidden, points, test::bench_noise(c.design, 78),
                                                      test::two_thread_for);
  const DiscrepancyResult r = run_discrepancy(baseline, data, {}, test::two_thread_for);
  const std::string trace = "\n  conclusion: " + r.conclusion + "\n  discovery: " + r.discovery.verdict;
  ASSERT_EQ(r.effects.size(), 1u) << trace;
  EXPECT_EQ(r.effects[0].name, c.effect) << trace;
  EXPECT_TRUE(r.superseded.empty()) << trace;
  EXPECT_EQ(r.discovery.outcome, DiscoveryOutcome::library_stands) << trace;
  // The groups really were tried: the screening saw them on the baseline.
  ASSERT_FALSE(r.discovery.screened.empty());
}

INSTANTIATE_TEST_SUITE_P(Designs, LibraryEffectTruth, ::testing::ValuesIn(kLibraryTruths), [](const auto& info) {
  return std::string(info.param.effect) + "_" + info.param.design.name;
});

// With the library's rounds switched off the step fits the groups alone (pairs included when
// the best single change leaves a structured residual): the best change of the base model must
// still explain a hidden droop worse than droop does, by more than the margin.
TEST(LibraryEffectTruthFullSearch, DroopStaysNamedWhenEveryChangeIsFitted) {
  const MotorParameters baseline = test::calibrated_motor();
  MotorParameters hidden = baseline;
  enable_effect(hidden, *find_candidate_effect("amplifier_droop"), 100.0);
  const test::Design design{"through_shuffled_60_spot", true, true, 60, 1, false, false};
  const std::vector<Measurement> points = test::design_points(design, 91);
  const MeasurementSet data = synthesize_measurements(hidden, points, test::bench_noise(design, 92),
                                                      test::two_thread_for);
  DiscrepancyOptions options;
  options.max_effects = 0;  // the library names nothing in its rounds ...
  const DiscrepancyResult without = run_discrepancy(baseline, data, options, test::two_thread_for);
  const DiscrepancyResult with = run_discrepancy(baseline, data, {}, test::two_thread_for);
  ASSERT_EQ(with.effects.size(), 1u) << with.conclusion;
  EXPECT_EQ(with.effects[0].name, "amplifier_droop");
  ASSERT_FALSE(without.discovery.fits.empty()) << without.discovery.verdict;
  EXPECT_GT(without.discovery.fits.front().delta_bic, with.effects[0].delta_bic + DiscrepancyOptions{}.bic_margin)
      << "a change of the base model explains droop as well as droop: " << without.discovery.verdict;
}

// An effect of the library and a change outside it, both hidden: both are named, the change
// beside the library's effect (the library names it first). (The other order - the change
// first, the effect by the library's rounds on the changed model - is found on some sessions
// and not on others: docs/discrepancy.md, "Limits".)
struct EffectAndChange {
  const char* effect;
  double effect_value;
  const char* group;
  double change;
  test::Design design;
};

void PrintTo(const EffectAndChange& c, std::ostream* os) { *os << c.effect << " and " << c.group; }

const EffectAndChange kEffectAndChange[] = {
    {"guide_friction", 0.05, "stator_damping", 1.3, {"through_ordered_60_sweeps", true, false, 60, 1, true, false}},
};

class LibraryEffectAndBaseChange : public ::testing::TestWithParam<EffectAndChange> {};

TEST_P(LibraryEffectAndBaseChange, BothAreNamed) {
  const EffectAndChange& c = GetParam();
  const MotorParameters baseline = test::calibrated_motor();
  MotorParameters hidden = baseline;
  enable_effect(hidden, *find_candidate_effect(c.effect), c.effect_value);
  group_free_parameter(*find_parameter_group(c.group), baseline).apply(hidden, c.change);
  const std::vector<Measurement> points = test::design_points(c.design, 93);
  const MeasurementSet data = synthesize_measurements(hidden, points, test::bench_noise(c.design, 94),
                                                      test::two_thread_for);
  const MeasurementSet clean = test::clean_readings(hidden, points, c.design);
  const DiscrepancyResult r = run_discrepancy(baseline, data, {}, test::two_thread_for);
  std::string trace = "\n  conclusion: " + r.conclusion + "\n  discovery: " + r.discovery.verdict;
  for (const DiscrepancyRound& round : r.rounds) trace += "\n  round: " + round.verdict;
  for (const GroupScreening& g : r.discovery.screened) {
    trace += "\n  screened " + g.name + " " + std::to_string(g.value) + " " + std::to_string(g.delta_bic);
  }
  for (const GroupFit& f : r.discovery.fits)
    trace += "\n  fit " + describe_group_fit(f) + " " + std::to_string(f.delta_bic);
  const GroupFit* change = accepted_change(r.discovery);
  ASSERT_NE(change, nullptr) << trace;
  ASSERT_EQ(change->groups.size(), 1u) << trace;
  EXPECT_EQ(change->groups[0], c.group) << trace;
  EXPECT_NEAR(change->values[0], c.change, 3.0 * change->standard_errors[0]) << trace;
  ASSERT_EQ(r.effects.size(), 1u) << trace;
  EXPECT_EQ(r.effects[0].name, c.effect) << trace;
  EXPECT_NEAR(r.effects[0].value, c.effect_value, 3.0 * r.effects[0].standard_error) << trace;
  const double before = test::held_out_gap_to_truth(data, clean, r.baseline_predictions, r.held_out);
  const double after = test::held_out_gap_to_truth(data, clean, r.augmented_predictions, r.held_out);
  EXPECT_LE(after, 0.3 * before) << "held-out gap to the truth " << before << " -> " << after << trace;
  RecordProperty("conclusion", r.conclusion);
}

INSTANTIATE_TEST_SUITE_P(Designs, LibraryEffectAndBaseChange, ::testing::ValuesIn(kEffectAndChange),
                         [](const auto& info) {
                           return std::string(info.param.effect) + "_and_" + info.param.group + "_" +
                                  info.param.design.name;
                         });

}  // namespace
}  // namespace swum
