// The discrepancy workflow on sessions shaped like users' data (issue 11, docs/discrepancy.md
// "Tests"): sweeps through the softening peak as well as above it, voltages in order and
// shuffled, 30 / 60 / 200 points, with and without repeats, spot points from rest and
// continuous downward sweeps, all quantities and speed only, loads 0-3 N; noise of a real bench
// (2.5 % multiplicative, a sensor floor; 5 Hz drive-frequency jitter in the noise-only sessions).
// A covering design: every
// feature level and every library effect appears at least once (not the full factorial).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <ostream>
#include <random>
#include <sstream>
#include <string>

#include "../discrepancy_test_support.h"
#include "../session_designs.h"
#include "../thread_pool_for.h"
#include "analysis/discrepancy/discrepancy.h"
#include "analysis/measurements/synthetic_measurements.h"
#include "formats/parameter_file.h"

namespace swum {
namespace {

using test::bench_noise;
using test::clean_readings;
using test::Design;
using test::design_points;
using test::uniform;

MotorParameters calibrated() { return test::calibrated_motor(); }

struct Case {
  Design design;
  const char* effect;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.effect << " on " << c.design.name; }

// Each feature level and each effect at least once.
const Case kCases[] = {
    {{"through_shuffled_60_spot", true, true, 60, 1, false, false}, "electroelastic"},
    {{"through_ordered_60_sweeps_speed", true, false, 60, 1, true, true}, "thermal"},
    {{"above_shuffled_30_repeats", false, true, 30, 2, false, false}, "wear"},
    {{"through_ordered_200_sweeps_speed", true, false, 200, 1, true, true}, "preload"},
    {{"above_ordered_60_repeats_speed", false, false, 60, 2, false, true}, "guide_friction"},
    {{"through_shuffled_200_spot", true, true, 200, 1, false, false}, "amplifier_droop"},
};

class UsersData : public ::testing::TestWithParam<Case> {};

TEST_P(UsersData, HiddenEffectIsNamedAloneRecoveredAndClosesTheGap) {
  const Case& c = GetParam();
  const CandidateEffect* effect = find_candidate_effect(c.effect);
  ASSERT_NE(effect, nullptr);
  // Magnitude drawn (seeded by the design's name) across the plausible range.
  std::uint64_t seed = 1469598103934665603ULL;
  for (const char* ch = c.design.name; *ch != 0; ++ch)
    seed = (seed ^ static_cast<unsigned char>(*ch)) * 1099511628211ULL;
  std::mt19937_64 rng(seed);
  const double truth = uniform(rng, effect->plausible_low, effect->plausible_high);
  const MotorParameters baseline = calibrated();
  MotorParameters hidden = baseline;
  enable_effect(hidden, *effect, truth);
  const std::vector<Measurement> points = design_points(c.design, seed);
  const MeasurementSet data = synthesize_measurements(hidden, points, bench_noise(c.design, seed + 1),
                                                      test::two_thread_for);
  const MeasurementSet clean = clean_readings(hidden, points, c.design);
  ASSERT_GE(data.rows.size(), points.size() * c.design.repeats * 9 / 10);

  const DiscrepancyResult r = run_discrepancy(baseline, data, {}, test::two_thread_for);
  std::string rounds;
  for (const auto& round : r.rounds) rounds += "\n  " + round.verdict;
  ASSERT_EQ(r.effects.size(), 1u) << "truth " << effect->name << " = " << truth << rounds;
  EXPECT_EQ(r.effects[0].name, effect->name) << rounds;
  // And the discovery step leaves it standing (no change of the base model beside or instead).
  EXPECT_EQ(r.discovery.outcome, DiscoveryOutcome::library_stands) << r.discovery.verdict;
  if (r.effects[0].name == effect->name) {
    const double se = r.effects[0].standard_error;
    ASSERT_TRUE(std::isfinite(se) && se > 0.0) << "standard error " << se;
    EXPECT_LT(se, 0.2 * std::abs(truth - effect->neutral)) << "the effect is not resolved";
    EXPECT_NEAR(r.effects[0].value, truth, 3.0 * se) << "standard error " << se << rounds;
  }
  const double before = test::held_out_gap_to_truth(data, clean, r.baseline_predictions, r.held_out);
  const double after = test::held_out_gap_to_truth(data, clean, r.augmented_predictions, r.held_out);
  EXPECT_LE(after, 0.3 * before) << "held-out gap to the truth " << before << " -> " << after;
  RecordProperty("truth", std::to_string(truth));
  RecordProperty("value", std::to_string(r.effects[0].value));
}

INSTANTIATE_TEST_SUITE_P(Designs, UsersData, ::testing::ValuesIn(kCases), [](const auto& info) {
  return std::string(info.param.effect) + "_" + info.param.design.name;
});

// Noise only, pooled over every design: at least 95 % of the sessions name nothing (no library
// effect and no change of the base model). The
// default run pools 60 sessions; SWUM_NEGATIVE_CONTROL_SESSIONS=200 is the longer run of
// docs/discrepancy.md. The count and its 95 % Clopper-Pearson upper bound are printed.
TEST(UsersDataNegativeControl, NamesNothingInAtLeast95PercentOfSessions) {
  int sessions = 60;
  if (const char* env = std::getenv("SWUM_NEGATIVE_CONTROL_SESSIONS")) sessions = std::max(6, std::atoi(env));
  const MotorParameters baseline = calibrated();
  // Smaller sessions than the effect designs (30-60 points) keep the default run short; the
  // 200-point designs are covered by the longer run.
  std::vector<Design> designs;
  for (const Case& c : kCases) {
    Design d = c.design;
    if (d.points > 60 && sessions <= 60) d.points = 60;
    designs.push_back(d);
  }
  // The sessions are independent: two at a time, one per core, each with the plain loop inside
  // (a session's own evaluations are often a single task, which would leave the second thread
  // of test::two_thread_for idle). Every session's result is the same as run alone; they are
  // counted in session order below.
  std::vector<std::string> conclusions(static_cast<std::size_t>(sessions));
  std::vector<char> session_named(static_cast<std::size_t>(sessions), 0);  // not vector<bool>: one byte each
  std::atomic<int> next_session{0};
  const auto run_sessions = [&] {
    for (int s = next_session++; s < sessions; s = next_session++) {
      const Design& d = designs[static_cast<std::size_t>(s) % designs.size()];
      const auto seed = static_cast<std::uint64_t>(7919 * (s + 1));
      const std::vector<Measurement> points = design_points(d, seed);
      const MeasurementSet data = synthesize_measurements(baseline, points, bench_noise(d, seed + 3, 5.0), serial_for);
      const DiscrepancyResult r = run_discrepancy(baseline, data, {}, serial_for);
      session_named[static_cast<std::size_t>(s)] = test::names_something(r) ? 1 : 0;  // an effect or a change
      conclusions[static_cast<std::size_t>(s)] = r.conclusion;
    }
  };
  test::on_two_threads([&](int) { run_sessions(); });
  int named = 0;
  std::string namings;
  std::vector<int> named_by_design(designs.size(), 0), sessions_by_design(designs.size(), 0);
  for (int s = 0; s < sessions; ++s) {
    const std::size_t which = static_cast<std::size_t>(s) % designs.size();
    const Design& d = designs[which];
    ++sessions_by_design[which];
    const auto seed = static_cast<std::uint64_t>(7919 * (s + 1));
    if (session_named[static_cast<std::size_t>(s)] != 0) {
      ++named;
      ++named_by_design[which];
      namings += std::string("\n  ") + d.name + " seed " + std::to_string(seed) + ": " +
                 conclusions[static_cast<std::size_t>(s)];
    }
  }
  // One-sided 95 % upper bound of the false-naming rate: the p with P(X <= named | p) = 0.05.
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 60; ++it) {
    const double p = 0.5 * (lo + hi);
    double cdf = 0.0, term = std::pow(1.0 - p, sessions);
    for (int k = 0; k <= named; ++k) {
      cdf += term;
      term *= (sessions - k) / (k + 1.0) * p / (1.0 - p);
    }
    (cdf > 0.05 ? lo : hi) = p;
  }
  std::printf("negative control: %d of %d sessions named an effect or a change (rate %.3f, 95 %% upper bound %.3f)\n",
              named, sessions, static_cast<double>(named) / sessions, hi);
  for (std::size_t k = 0; k < designs.size(); ++k) {
    std::printf("  %-36s %d of %d named\n", designs[k].name, named_by_design[k], sessions_by_design[k]);
  }
  EXPECT_LE(named * 20, sessions) << namings;
}

}  // namespace
}  // namespace swum
