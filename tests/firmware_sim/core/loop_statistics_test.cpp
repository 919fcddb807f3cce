#include "core/loop_statistics.h"

#include <gtest/gtest.h>

namespace swum::emu {
namespace {

TEST(Histogram, BucketsAreMonotoneAndTight) {
  std::size_t last = 0;
  for (std::uint64_t v = 0; v < 5'000'000; v += (v < 1000 ? 1 : v / 97)) {
    const std::size_t b = Histogram::bucket_of(v);
    EXPECT_GE(b, last);
    last = b;
    EXPECT_GE(Histogram::bucket_upper(b), v);
    EXPECT_LE(static_cast<double>(Histogram::bucket_upper(b)), static_cast<double>(v) * 1.016 + 1.0) << v;
  }
  EXPECT_LT(Histogram::bucket_of(~std::uint64_t{0}), Histogram::kBuckets);
}

TEST(Histogram, Percentiles) {
  Histogram h;
  for (std::uint64_t i = 1; i <= 1000; ++i) h.record(i * 1000);  // 1..1000 us
  EXPECT_EQ(h.count(), 1000U);
  EXPECT_EQ(h.max(), 1'000'000U);
  EXPECT_NEAR(static_cast<double>(h.percentile(0.5)), 500'000.0, 500'000.0 * 0.016);
  EXPECT_NEAR(static_cast<double>(h.percentile(0.99)), 990'000.0, 990'000.0 * 0.016);
  EXPECT_NEAR(static_cast<double>(h.percentile(0.999)), 999'000.0, 999'000.0 * 0.016);
  EXPECT_EQ(h.percentile(1.0), 1'000'000U);
  EXPECT_DOUBLE_EQ(h.mean(), 500'500.0);
}

TEST(LoopStatistics, SummaryCountsOverruns) {
  LoopStatistics s;
  for (int i = 0; i < 100; ++i) s.record(1000, 20000, i % 10 == 0);
  const LoopStatsSummary sum = s.summary();
  EXPECT_EQ(sum.ticks, 100U);
  EXPECT_EQ(sum.overruns, 10U);
  EXPECT_EQ(sum.lateness_max_ns, 1000U);
  EXPECT_EQ(sum.compute_p99_ns, 20000U);
  EXPECT_NE(format_summary(sum, 10000).find("overruns  10"), std::string::npos);
}

TEST(DropCounters, CountAndReportInTheOrderAsked) {
  DropCounters drops;
  EXPECT_EQ(drops.count(Drop::no_slot), 1U);
  EXPECT_EQ(drops.count(Drop::no_slot), 2U);
  drops.count(Drop::frame_timeout);
  EXPECT_EQ(drops[Drop::no_slot], 2U);
  EXPECT_EQ(drops[Drop::idle], 0U);
  EXPECT_EQ(format_drops("tcp closed:", drops, {Drop::no_slot, Drop::idle, Drop::frame_timeout}),
            "  tcp closed: no slot 2, idle 0, frame timeout 1\n");
  for (int d = 0; d < static_cast<int>(Drop::kCount); ++d) EXPECT_STRNE(to_string(static_cast<Drop>(d)), "?");
}

}  // namespace
}  // namespace swum::emu
