// The draws of `swum population`: a function of (seed, motor, parameter) alone, whatever the
// order or thread; the distributions they follow; the statistics of the summary.
#include "analysis/studies/population.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "../thread_pool_for.h"
#include "formats/spread_file.h"

namespace swum {
namespace {

const char* const kSpreads = "[stator]\n"
                             "target_l1_frequency_hz = { distribution = \"normal\", sigma = 80, truncate = 2 }\n"
                             "[contact]\n"
                             "preload_n = { distribution = \"normal\", sigma_percent = 5 }\n"
                             "friction_coefficient = { distribution = \"uniform\", min = 0.3, max = 0.4 }\n";

std::vector<ParameterSpread> spreads(const char* text = kSpreads) {
  return parse_parameter_spreads(text, "spreads.toml", MotorParameters{});
}

TEST(PopulationDraw, AMotorsValuesDependOnSeedAndMotorOnlyNotOnOrderOrThread) {
  const auto s = spreads();
  constexpr std::uint64_t kMotors = 200;
  std::vector<std::vector<double>> forward;
  for (std::uint64_t i = 0; i < kMotors; ++i) forward.push_back(draw_spread_values(s, 7, i));
  // Backwards, and interleaved over two threads.
  std::vector<std::vector<double>> backward(kMotors);
  for (std::uint64_t i = kMotors; i-- > 0;) backward[i] = draw_spread_values(s, 7, i);
  std::vector<std::vector<double>> threaded(kMotors);
  test::on_two_threads([&](int which) {
    for (auto i = static_cast<std::uint64_t>(which); i < kMotors; i += 2) threaded[i] = draw_spread_values(s, 7, i);
  });
  EXPECT_EQ(forward, backward);
  EXPECT_EQ(forward, threaded);
  // Another seed, another motor: other values.
  EXPECT_NE(draw_spread_values(s, 8, 3), forward[3]);
  EXPECT_NE(forward[4], forward[3]);
}

TEST(PopulationDraw, AParametersValuesDoNotDependOnWhichOtherParametersVary) {
  const auto all = spreads();
  const auto preload_only = spreads("[contact]\npreload_n = { distribution = \"normal\", sigma_percent = 5 }\n");
  ASSERT_EQ(preload_only.size(), 1u);
  for (std::uint64_t i = 0; i < 50; ++i) {
    EXPECT_EQ(draw_spread_values(preload_only, 3, i)[0], draw_spread_values(all, 3, i)[1]) << "motor " << i;
  }
}

TEST(PopulationDraw, DrawsFollowTheirDistributionsWithinTheirTruncation) {
  const auto s = spreads();
  constexpr int kMotors = 4000;
  std::vector<double> l1, preload, mu;
  for (int i = 0; i < kMotors; ++i) {
    const auto v = draw_spread_values(s, 11, static_cast<std::uint64_t>(i));
    l1.push_back(v[0]);
    preload.push_back(v[1]);
    mu.push_back(v[2]);
  }
  const auto mean = [](const std::vector<double>& x) {
    double sum = 0.0;
    for (double v : x) sum += v;
    return sum / static_cast<double>(x.size());
  };
  const auto sd = [&](const std::vector<double>& x) {
    const double m = mean(x);
    double sum = 0.0;
    for (double v : x) sum += (v - m) * (v - m);
    return std::sqrt(sum / static_cast<double>(x.size() - 1));
  };
  const double nominal_l1 = MotorParameters{}.stator.target_l1_frequency_hz;
  EXPECT_NEAR(mean(l1), nominal_l1, 4.0);  // ~3 standard errors
  // A normal truncated at 2 sigma has standard deviation 0.880 sigma.
  EXPECT_NEAR(sd(l1), 0.880 * 80.0, 3.0);
  EXPECT_GE(*std::min_element(l1.begin(), l1.end()), nominal_l1 - 160.0);
  EXPECT_LE(*std::max_element(l1.begin(), l1.end()), nominal_l1 + 160.0);
  EXPECT_NEAR(mean(preload), 24.8, 0.05);
  EXPECT_NEAR(sd(preload), 0.9866 * 1.24, 0.05);  // truncated at 3 sigma: 0.9866 sigma
  EXPECT_NEAR(mean(mu), 0.35, 0.002);
  EXPECT_NEAR(sd(mu), 0.1 / std::sqrt(12.0), 0.002);
  EXPECT_GE(*std::min_element(mu.begin(), mu.end()), 0.3);
  EXPECT_LE(*std::max_element(mu.begin(), mu.end()), 0.4);
}

TEST(PopulationDraw, ZeroSpreadGivesTheNominalValueExactly) {
  const auto s = spreads("[contact]\npreload_n = { distribution = \"normal\", sigma = 0 }\n"
                         "stiffness_n_m = { distribution = \"uniform\", half_width = 0 }\n");
  const MotorParameters p = with_drawn_values(MotorParameters{}, s, draw_spread_values(s, 1, 5));
  EXPECT_EQ(p.contact.preload_n, MotorParameters{}.contact.preload_n);
  EXPECT_EQ(p.contact.stiffness_n_m, MotorParameters{}.contact.stiffness_n_m);
}

TEST(PopulationStatistics, PercentilesInterpolateBetweenOrderStatistics) {
  std::vector<double> v;
  for (int i = 100; i >= 0; --i) v.push_back(i);  // 0..100, unsorted
  const Distribution d = describe_distribution(v);
  EXPECT_EQ(d.count, 101u);
  EXPECT_DOUBLE_EQ(d.min, 0.0);
  EXPECT_DOUBLE_EQ(d.p5, 5.0);
  EXPECT_DOUBLE_EQ(d.p50, 50.0);
  EXPECT_DOUBLE_EQ(d.p95, 95.0);
  EXPECT_DOUBLE_EQ(d.max, 100.0);
  const Distribution two = describe_distribution({1.0, 2.0});
  EXPECT_DOUBLE_EQ(two.p5, 1.05);
  EXPECT_DOUBLE_EQ(two.p50, 1.5);
  EXPECT_EQ(describe_distribution({}).count, 0u);
}

TEST(PopulationStatistics, TheNarrowestBandCoversTheYieldsShareOfWholeSpans) {
  using Span = std::optional<std::pair<double, double>>;
  // Ten motors: eight between 40000 and 40200, one far low, one undecided.
  std::vector<Span> spans;
  for (int i = 0; i < 8; ++i) spans.push_back(std::pair{40000.0 + 25.0 * i, 40000.0 + 25.0 * i});
  spans.push_back(std::pair{39000.0, 39100.0});
  spans.push_back(std::nullopt);
  FrequencyBand b = narrowest_band(spans, 0.8);  // 8 motors
  ASSERT_TRUE(b.reached);
  EXPECT_EQ(b.needed, 8u);
  EXPECT_DOUBLE_EQ(b.low_hz, 40000.0);
  EXPECT_DOUBLE_EQ(b.high_hz, 40175.0);
  EXPECT_EQ(b.covered, 8u);
  b = narrowest_band(spans, 0.7);  // 7 motors: the lowest of the equally narrow bands
  EXPECT_DOUBLE_EQ(b.low_hz, 40000.0);
  EXPECT_DOUBLE_EQ(b.high_hz, 40150.0);
  b = narrowest_band(spans, 0.9);  // 9 motors: must reach down to the far one
  EXPECT_DOUBLE_EQ(b.low_hz, 39000.0);
  EXPECT_DOUBLE_EQ(b.high_hz, 40175.0);
  EXPECT_FALSE(narrowest_band(spans, 0.95).reached);  // 10 needed, one is undecided
  // A motor whose span (over the voltages) is wide forces the band to hold all of it.
  spans = {std::pair{40000.0, 40500.0}, std::pair{40100.0, 40100.0}};
  b = narrowest_band(spans, 1.0);
  EXPECT_DOUBLE_EQ(b.low_hz, 40000.0);
  EXPECT_DOUBLE_EQ(b.high_hz, 40500.0);
}

}  // namespace
}  // namespace swum
