// `swum pick` on the real binary: an offline model sweep, then the JSON contract, the
// schedule file, higher voltage -> lower frequency, and refusal of a too-coarse sweep.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "swum_cli_runner.h"
#include "test_paths.h"

namespace {

using swum::test::run_swum;
const std::string kConfig = swum::test::source_path("config/li2019.toml");

TEST(SwumPick, PicksLowerFrequencyAtHigherVoltageWithAGainOverNaive) {
  const auto sweep = swum::test::scratch_path("pick", "sweep.csv");
  const auto schedule = swum::test::scratch_path("pick", "schedule.csv");
  auto r = run_swum({"sweep", "--config", kConfig, "--amplitude-v", "100,300,400", "--frequency", "39300:40600:50",
                     "--out", sweep.string()});
  ASSERT_EQ(r.status, 0) << r.output;
  r = run_swum(
      {"pick", "--sweep", sweep.string(), "--amplitude-v", "100,300,400", "--json", "--schedule", schedule.string()});
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j.size(), 3u);
  double previous = 1e9;
  for (const auto& p : j) {
    for (const char* key : {"amplitude_v", "frequency_hz", "speed_mm_s", "naive_speed_mm_s"}) {
      ASSERT_TRUE(p.at(key).is_number()) << key << " " << p.dump();
    }
    EXPECT_LT(p.at("frequency_hz").get<double>(), previous) << p.dump();
    previous = p.at("frequency_hz").get<double>();
    if (p.at("amplitude_v").get<double>() >= 300.0) {
      EXPECT_GT(p.at("speed_mm_s").get<double>(), 1.2 * p.at("naive_speed_mm_s").get<double>());
      EXPECT_LT(p.at("drift_hz").get<double>(), -300.0);
    }
  }
  EXPECT_EQ(swum::test::read_file(schedule).substr(0, 25), "amplitude_v,frequency_hz\n");
}

TEST(SwumPick, RefusesATooCoarseSweepWithAReason) {
  const auto sweep = swum::test::scratch_path("pick", "coarse.csv");
  auto r = run_swum({"sweep", "--config", kConfig, "--amplitude-v", "100", "--frequency", "39300:40600:400", "--out",
                     sweep.string()});
  ASSERT_EQ(r.status, 0) << r.output;
  r = run_swum({"pick", "--sweep", sweep.string(), "--amplitude-v", "100"});
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("undecided"), std::string::npos) << r.output;
}

}  // namespace
