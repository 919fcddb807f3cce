// The held-out test of the discrepancy workflow (src/analysis/fit/held_out_test.h): exact
// signed-rank tails checked against hand-counted sign patterns, ties, the normal approximation,
// and the pooling of a point's values.
#include "analysis/fit/held_out_test.h"

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
  // The same statistic near p = 0.05 counted exactly (300 points) and approximated (301: the
  // extra point is the smallest, worse, so it barely moves W+): the two tails agree closely.
  std::vector<double> d;
  for (int i = 1; i <= 300; ++i) d.push_back((i % 2 == 0 ? 1.0 : -1.0) * (i + 10));
  // Flip worse points to better, largest first, until the one-sided p is a few per cent.
  double exact = signed_rank_p_value(d);
  for (std::size_t i = d.size(); i-- > 0 && exact > 0.05;) {
    if (d[i] < 0.0) d[i] = -d[i];
    exact = signed_rank_p_value(d);
  }
  ASSERT_GT(exact, 0.005);
  ASSERT_LT(exact, 0.2);
  d.push_back(-0.5);
  const double approx = signed_rank_p_value(d);
  EXPECT_NEAR(approx, exact, 0.15 * exact);
  std::vector<double> balanced;
  for (int i = 1; i <= 400; ++i) balanced.push_back((i % 2 == 0 ? -1.0 : 1.0) * i);
  EXPECT_NEAR(signed_rank_p_value(balanced), 0.5, 0.1);
}

TEST(SignFlip, ExactTailCountsSignPatterns) {
  // Sums of +-1, +-2, +-4: the 8 patterns give 8 distinct sums; 7 is the largest (p = 1/8);
  // 3 (= 1 - 2 + 4) is reached or beaten by 3, 5 and 7 (p = 3/8).
  EXPECT_DOUBLE_EQ(sign_flip_p_value(std::vector<double>{1.0, 2.0, 4.0}), 1.0 / 8.0);
  EXPECT_DOUBLE_EQ(sign_flip_p_value(std::vector<double>{1.0, -2.0, 4.0}), 3.0 / 8.0);  // 3, 5, 7
  EXPECT_DOUBLE_EQ(sign_flip_p_value(std::vector<double>{}), 1.0);
}

TEST(SignFlip, OneWildPointCannotCarryIt) {
  // One large improvement among small balanced differences: the patterns that keep its sign
  // (half of them) and do not lose on the rest (P(at least 7 of 14 positive) = 0.605) reach it,
  // p = 0.30 - far from any level.
  std::vector<double> d{50.0};
  for (int i = 0; i < 14; ++i) d.push_back(i % 2 == 0 ? 0.1 : -0.1);
  EXPECT_NEAR(sign_flip_p_value(d), 0.5 * 0.6047, 0.001);
}

TEST(SignFlip, RandomPatternsAgreeWithTheExactCountAbove20) {
  // 21 equal improvements but 7 worse: the exact tail is P(Binomial(21, 1/2) <= 7) = 0.0946.
  std::vector<double> d;
  for (int i = 0; i < 21; ++i) d.push_back(i < 7 ? -1.0 : 1.0);
  EXPECT_NEAR(sign_flip_p_value(d), 0.0946, 0.004);
}

TEST(HeldOut, PoolsTheValuesOfOnePointAndBootstrapsTheReduction) {
  // Two quantities at each of 12 points: one test per point, not per value.
  MeasurementSet set;
  set.has_quantity = {true, true, false};
  for (int i = 0; i < 12; ++i) {
    Measurement m;
    m.amplitude_v = 100.0 + i;
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
