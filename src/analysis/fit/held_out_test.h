// Does a fitted candidate predict held-out operating points better than the current model?
// (docs/discrepancy.md, "Selection"): the residuals of one operating point (its quantities and
// repeats, which share the point's errors) are pooled into one error per point, and the paired
// per-point differences are tested with the one-sided Wilcoxon signed-rank test. Ranks make
// the test robust to the heavy tails of residuals near the resonance collapse, where a handful
// of points would dominate any mean of squares; its null distribution (every sign equally
// likely: the candidate is no better than the current model) is exact, counted over the 2^m
// sign patterns, for up to 300 points, and the normal approximation with tie correction above.
// Ranks weigh every point alike. The second test, Fisher-Pitman's sign-flip test of
// S = sum (e0^2 - e1^2) (the reduction of the squared error itself), weighs each point by the
// squared error it removed, so large gains with small losses elsewhere count more (it still
// needs some 7 gaining points to reach 0.005: with k carrying the gain, p >~ 2^-(k+1)); its null
// distribution is the same sign symmetry, exact over all 2^m patterns up to m = 20 and from
// 200 000 seeded random patterns above. A single wild point cannot carry it: flipping that
// point's sign is half of its null distribution. The two are combined by Bonferroni: the
// evidence p is twice the smaller one, so the level of the combination is the stated one.
// A percentile bootstrap over the held-out points gives an interval of the relative RMS
// reduction, reported as the size of the improvement.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "analysis/fit/disagreement_map.h"
#include "analysis/measurements/measurements.h"

namespace swum {

struct HeldOutEvidence {
  int points = 0;              // held-out operating points compared
  int improved = 0;            // points whose pooled error went down
  int unchanged = 0;           // points whose error did not change at all (left out of the ranks)
  double signed_rank = 0.0;    // W+: sum of the ranks of the improvements
  double signed_rank_p = 1.0;  // one-sided P(W+ >= observed) under "no better"
  double sign_flip_p = 1.0;    // one-sided P(S >= observed), S = sum of e0^2 - e1^2, random signs
  double p_value = 1.0;        // combined: 2 min(signed_rank_p, sign_flip_p), at most 1
  double rms_before = 0.0;     // relative, over the held-out values
  double rms_after = 0.0;
  double reduction = 0.0;      // 1 - rms_after / rms_before
  double reduction_low = 0.0;  // 90 % percentile-bootstrap interval of the reduction
  double reduction_high = 0.0;
};

// Which operating points are held out for scoring: `fraction` of them, but at least
// `min_points` (never more than half), chosen in a seeded random order.
struct HeldOutSplit {
  double fraction = 0.25;
  int min_points = 12;
  std::uint64_t seed = 2019;
};

// Held-out flag per row: operating points (amplitude_v, frequency, load; a point's repeats stay
// together, whatever their time) in a seeded random order; the first of them are held out.
// held_points / point_count receive the counts.
[[nodiscard]] std::vector<bool> held_out_rows(const MeasurementSet& set, const HeldOutSplit& split, int& held_points,
                                              int& point_count);

// One-sided exact (m <= 300) or normal-approximation p-value of the signed-rank statistic of
// `differences` (> 0: improvement). Zero differences are dropped (Wilcoxon's convention); ties
// get mid-ranks. Returns 1 when nothing is left.
[[nodiscard]] double signed_rank_p_value(std::span<const double> differences, double* w_plus = nullptr);

// One-sided p-value of the sign-flip test of sum(differences) (> 0: improvement); `seed` fixes
// the random patterns used above 20 values. Returns 1 for no values.
[[nodiscard]] double sign_flip_p_value(std::span<const double> differences, std::uint64_t seed = 2019);

// Compares residuals r0 (current model) and r1 (candidate) over the held-out slots; values are
// grouped by operating point (amplitude_v, frequency, load). `seed` fixes the bootstrap.
[[nodiscard]] HeldOutEvidence compare_held_out(const MeasurementSet& set, const ResidualModel& model,
                                               std::span<const double> r0, std::span<const double> r1,
                                               std::span<const std::size_t> held_out_slots, std::uint64_t seed = 2019);

}  // namespace swum
