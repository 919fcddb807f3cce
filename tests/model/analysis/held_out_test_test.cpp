// The held-out test of the discrepancy workflow (src/analysis/held_out_test.h): exact
// signed-rank tails checked against hand-counted sign patterns, ties, the normal approximation,
// and the pooling of a point's values.
#include "analysis/held_out_test.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace swum {
namespace {

TEST(SignedRank, AllImprovedHasTheSmallestExactTail) {
  const std::vector<double> d{0.1, 0.2, 0.3, 0.4, 0.5};
  double w = 0.0;
  EXPECT_DOUBLE_EQ(signed_rank_p_value(d, &w), 1.0 / 32.0);  // one pattern of 2^5
  EXPECT_DOUBLE_EQ(w, 15.0);
}

TEST(SignedRank, SmallestDifferenceWorseCountsTwoPatterns) {
  // W+ = 14 of 15: the patterns {all +} and {only rank 1 -} reach it.
  EXPECT_DOUBLE_EQ(signed_rank_p_value(std::vector<double>{-0.1, 0.2, 0.3, 0.4, 0.5}), 2.0 / 32.0);
}

TEST(SignedRank, AllWorseGivesOne) {
  EXPECT_DOUBLE_EQ(signed_rank_p_value(std::vector<double>{-1.0, -2.0, -3.0}), 1.0);
}

TEST(SignedRank, ZerosAreDroppedAndNothingLeftIsNoEvidence) {
  EXPECT_DOUBLE_EQ(signed_rank_p_value(std::vector<double>{0.0, 0.0}), 1.0);
  EXPECT_DOUBLE_EQ(signed_rank_p_value(std::vector<double>{0.0, 0.5, 0.7}), 0.25);
}

TEST(SignedRank, TiesGetMidRanks) {
  // |d| = 1, 1, 2: mid-ranks 1.5, 1.5, 3; W+ = 4.5 (the negative one tied). Patterns with
  // W+ >= 4.5: {+,+,+} 6, {-,+,+} 4.5, {+,-,+} 4.5 -> 3 of 8.
  double w = 0.0;
  EXPECT_DOUBLE_EQ(signed_rank_p_value(std::vector<double>{-1.0, 1.0, 2.0}, &w), 3.0 / 8.0);
  EXPECT_DOUBLE_EQ(w, 4.5);
}

TEST(SignedRank, NormalApproximationAgreesWithTheExactTailAtTheBoundary) {
  // 300 points is still exact; 301 uses the normal approximation. Alternating signs with a
  // slight excess of improvements: both tails near the middle and close to each other.
  std::vector<double> d;
  for (int i = 1; i <= 301; ++i) d.push_back((i % 3 == 0 ? -1.0 : 1.0) * i);
  const double approx = signed_rank_p_value(d);
  d.pop_back();
  const double exact = signed_rank_p_value(d);
  EXPECT_GT(exact, 0.0);
  EXPECT_LT(exact, 1e-6);  // two thirds improved, over 300 points: overwhelming
  EXPECT_LT(approx, 1e-6);
  std::vector<double> balanced;
  for (int i = 1; i <= 400; ++i) balanced.push_back((i % 2 == 0 ? -1.0 : 1.0) * i);
  EXPECT_NEAR(signed_rank_p_value(balanced), 0.5, 0.1);
}

TEST(HeldOut, PoolsTheValuesOfOnePointAndBootstrapsTheReduction) {
  // Two quantities at each of 12 points: one test per point, not per value.
  MeasurementSet set;
  set.has_quantity = {true, true, false};
  for (int i = 0; i < 12; ++i) {
    Measurement m;
    m.vpp = 100.0 + i;
    m.frequency_hz = 40000.0;
    m.values = {100.0, 1.0, std::nullopt};
    set.rows.push_back(m);
  }
  const ResidualModel model(set, 0.05);
  ASSERT_EQ(model.slots().size(), 24u);
  std::vector<double> r0(24), r1(24);
  std::vector<std::size_t> slots;
  for (std::size_t k = 0; k < 24; ++k) {
    r0[k] = 0.2;
    r1[k] = k < 2 ? 0.3 : 0.02;  // point 0 gets worse, the rest much better
    slots.push_back(k);
  }
  const HeldOutEvidence e = compare_held_out(set, model, r0, r1, slots);
  EXPECT_EQ(e.points, 12);
  EXPECT_EQ(e.improved, 11);
  EXPECT_LT(e.p_value, 0.01);
  EXPECT_NEAR(e.rms_before, 0.2, 1e-12);
  EXPECT_GT(e.reduction, 0.5);
  EXPECT_LE(e.reduction_low, e.reduction);
  EXPECT_GE(e.reduction_high, e.reduction);
}

}  // namespace
}  // namespace swum
