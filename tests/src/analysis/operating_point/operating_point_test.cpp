// pick_operating_point on synthetic curves.
#include "analysis/operating_point/operating_point.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace {

using swum::CurveSample;
using swum::pick_operating_point;

// Lorentzian-like peak at f0 (Hz), height h, half width w; points 39300..40600 step `step`.
std::vector<CurveSample> peak_curve(double f0, double h, double w, double step = 50.0, double jump_below = -1.0) {
  std::vector<CurveSample> c;
  for (double f = 39300.0; f <= 40600.0 + 1e-9; f += step) {
    double v = h / (1.0 + std::pow((f - f0) / w, 2));
    if (jump_below > 0.0 && f < jump_below) v = -20.0;
    c.push_back({f, v});
  }
  return c;
}

TEST(PickOperatingPoint, CleanPeakGetsTheDefaultMarginAboveThePeak) {
  const auto r = pick_operating_point(peak_curve(40000.0, 300.0, 300.0));
  ASSERT_TRUE(r.decided) << r.reason;
  EXPECT_NEAR(r.peak_frequency_hz, 40000.0, 1e-6);  // symmetric about a grid point: the vertex is on it
  EXPECT_DOUBLE_EQ(r.grid_step_hz, 50.0);
  EXPECT_DOUBLE_EQ(r.margin_hz, swum::kDefaultMarginHz);
  EXPECT_DOUBLE_EQ(r.frequency_hz, 40100.0);
  // Interpolated between the points at 40100 and 40150: here the measured one.
  EXPECT_NEAR(r.speed_mm_s, 300.0 / (1.0 + std::pow(100.0 / 300.0, 2)), 1e-9);
  ASSERT_TRUE(r.naive_speed_mm_s.has_value());
  EXPECT_NEAR(*r.naive_speed_mm_s, 300.0 / (1.0 + std::pow(400.0 / 300.0, 2)), 1e-9);
}

TEST(PickOperatingPoint, WithoutAUserMarginTheGridStepIsTheFloor) {
  swum::PickOptions o;
  o.min_margin_hz = 0.0;
  const auto r = pick_operating_point(peak_curve(40000.0, 300.0, 300.0), o);
  ASSERT_TRUE(r.decided) << r.reason;
  EXPECT_GE(r.margin_hz, 50.0);
  EXPECT_LE(r.margin_hz, 100.0);
  EXPECT_DOUBLE_EQ(r.frequency_hz, std::ceil(r.peak_frequency_hz + r.margin_hz - 1e-6));
  EXPECT_GT(r.speed_mm_s, 0.9 * 300.0);
}

// A parabolic top between grid points: the peak is located off the grid (the vertex through the
// best point and its neighbours), so a 50 Hz and a 25 Hz grid give the same operating frequency.
std::vector<CurveSample> parabola_curve(double f0, double step) {
  std::vector<CurveSample> c;
  for (double f = 39300.0; f <= 40600.0 + 1e-9; f += step) c.push_back({f, 300.0 - 2e-4 * (f - f0) * (f - f0)});
  return c;
}

TEST(PickOperatingPoint, ThePeakIsLocatedFinerThanTheGrid) {
  for (double step : {50.0, 25.0, 10.0}) {
    const auto r = pick_operating_point(parabola_curve(40012.0, step));
    ASSERT_TRUE(r.decided) << step << ": " << r.reason;
    EXPECT_NEAR(r.peak_frequency_hz, 40012.0, 1e-6) << step;
    EXPECT_DOUBLE_EQ(r.frequency_hz, 40112.0) << step;
    EXPECT_NEAR(r.speed_mm_s, 300.0 - 2e-4 * 100.0 * 100.0, 2e-4 * step * step / 4.0) << step;  // linear between points
  }
}

TEST(PickOperatingPoint, SofteningCurveWithJumpStaysAboveTheCollapse) {
  // Skewed: rises slowly from above, peaks at 39500 and collapses below it.
  auto c = peak_curve(39500.0, 800.0, 600.0, 50.0, 39480.0);
  const auto r = pick_operating_point(c);
  ASSERT_TRUE(r.decided) << r.reason;
  EXPECT_DOUBLE_EQ(r.peak_frequency_hz, 39500.0);
  ASSERT_TRUE(r.collapse_hz.has_value());
  EXPECT_DOUBLE_EQ(*r.collapse_hz, 39450.0);
  EXPECT_GT(r.frequency_hz, r.peak_frequency_hz);
  EXPECT_GE(r.frequency_hz - r.peak_frequency_hz, r.margin_hz - 1e-9);
  EXPECT_GE(r.margin_hz, 50.0);
  // The lobe below the collapse, however high, is not part of the resonance.
  c.front().speed_mm_s = 5000.0;
  EXPECT_DOUBLE_EQ(pick_operating_point(c).peak_frequency_hz, 39500.0);
}

TEST(PickOperatingPoint, UserMarginIsAFloor) {
  swum::PickOptions o;
  o.min_margin_hz = 175.0;
  const auto r = pick_operating_point(peak_curve(40000.0, 300.0, 300.0), o);
  ASSERT_TRUE(r.decided) << r.reason;
  EXPECT_DOUBLE_EQ(r.frequency_hz, 40175.0);
}

TEST(PickOperatingPoint, FlatNoisyCurveIsRefused) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 8.0);
  std::vector<CurveSample> c;
  for (double f = 39300.0; f <= 40600.0; f += 50.0) c.push_back({f, 100.0 + noise(rng)});
  const auto r = pick_operating_point(c);
  EXPECT_FALSE(r.decided);
  EXPECT_FALSE(r.reason.empty());
}

TEST(PickOperatingPoint, NoisyPeakIsRefused) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 60.0);
  auto c = peak_curve(40000.0, 300.0, 300.0);
  for (auto& p : c) p.speed_mm_s += noise(rng);
  EXPECT_FALSE(pick_operating_point(c).decided);
}

TEST(PickOperatingPoint, MeasuredSpreadWidensTheMargin) {
  swum::PickOptions o;
  o.min_margin_hz = 0.0;  // the noise term alone
  auto c = peak_curve(40000.0, 300.0, 300.0);
  const auto clean = pick_operating_point(c, o);
  for (auto& p : c) p.spread_mm_s = 4.0;
  const auto r = pick_operating_point(c, o);
  ASSERT_TRUE(r.decided) << r.reason;
  EXPECT_GT(r.margin_hz, 50.0);
  EXPECT_GT(r.margin_hz, clean.margin_hz);
}

TEST(PickOperatingPoint, SinglePointIsRefused) {
  const auto r = pick_operating_point({{40000.0, 300.0}});
  EXPECT_FALSE(r.decided);
  EXPECT_NE(r.reason.find("too few points"), std::string::npos) << r.reason;
}

TEST(PickOperatingPoint, TooCoarseGridIsRefused) {
  const auto r = pick_operating_point(peak_curve(40300.0, 120.0, 150.0, 200.0));
  EXPECT_FALSE(r.decided);
}

TEST(PickOperatingPoint, PeakAtTheTopOfTheSweepIsRefused) {
  const auto r = pick_operating_point(peak_curve(41000.0, 300.0, 300.0));
  EXPECT_FALSE(r.decided);
  EXPECT_NE(r.reason.find("sweep higher"), std::string::npos) << r.reason;
}

TEST(PickOperatingPoint, UnsortedInputGivesTheSameAnswer) {
  auto c = peak_curve(39500.0, 800.0, 600.0, 50.0, 39480.0);
  const auto sorted = pick_operating_point(c);
  std::mt19937 rng(11);
  std::shuffle(c.begin(), c.end(), rng);
  const auto shuffled = pick_operating_point(c);
  ASSERT_TRUE(shuffled.decided) << shuffled.reason;
  EXPECT_DOUBLE_EQ(shuffled.frequency_hz, sorted.frequency_hz);
  EXPECT_DOUBLE_EQ(shuffled.speed_mm_s, sorted.speed_mm_s);
}

TEST(PickOperatingPoint, FailedPointBelowThePeakIsACollapse) {
  auto c = peak_curve(39500.0, 800.0, 600.0);
  for (auto& p : c)
    if (p.frequency_hz < 39480.0) p.ok = false;
  const auto r = pick_operating_point(c);
  ASSERT_TRUE(r.decided) << r.reason;
  EXPECT_DOUBLE_EQ(r.peak_frequency_hz, 39500.0);
}

}  // namespace
