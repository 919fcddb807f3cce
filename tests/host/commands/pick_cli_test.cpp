// `swum pick` on the real binary: an offline model sweep, then the JSON contract, the
// schedule file, higher voltage -> lower frequency, and refusal of a too-coarse sweep; the one
// operating point: `swum pick --config` and `swum band` agree exactly for the same motor, voltage,
// load, margin and grid (issue 34), and a pick's --load is a list like band's.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "swum_cli_runner.h"
#include "test_paths.h"

namespace {

using swum::test::run_swum;
const std::string kConfig = swum::test::source_path("config/li2019.toml");

TEST(SwumPick, PicksLowerFrequencyAtHigherVoltageWithAGainOverNaive) {
  const auto sweep = swum::test::scratch_path("pick", "sweep.csv");
  const auto schedule = swum::test::scratch_path("pick", "schedule.csv");
  auto r = run_swum({"sweep", "--config", kConfig, "--amplitude-v", "100,300,400", "--frequency-hz", "39300:40600:50",
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
  EXPECT_EQ(swum::test::read_file(schedule).substr(0, 32), "amplitude_v,load_n,frequency_hz\n");
}

TEST(SwumPick, RefusesATooCoarseSweepWithAReason) {
  const auto sweep = swum::test::scratch_path("pick", "coarse.csv");
  auto r = run_swum({"sweep", "--config", kConfig, "--amplitude-v", "100", "--frequency-hz", "39300:40600:400", "--out",
                     sweep.string()});
  ASSERT_EQ(r.status, 0) << r.output;
  r = run_swum({"pick", "--sweep", sweep.string(), "--amplitude-v", "100"});
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("undecided"), std::string::npos) << r.output;
}

// The same frequency from both commands: the same down-sweep (down_sweep_chain), the same rule
// (pick_operating_point, the peak refined off the grid) and the same defaults. Tolerance: none -
// the curves are the same bits, so the frequencies, peaks and speeds are equal exactly. Several
// voltages and loads (one list each, rows voltage-major in both), the default margin and grid,
// then another margin on a coarser grid given to both.
void expect_pick_equals_band(const std::vector<std::string>& extra) {
  std::vector<std::string> pick = {"pick",        "--config", kConfig, "--amplitude-v",
                                   "100,250,400", "--load",   "0,1.5", "--json"};
  std::vector<std::string> band = {"band",        "--config", kConfig, "--amplitude-v",
                                   "100,250,400", "--load",   "0,1.5", "--json"};
  pick.insert(pick.end(), extra.begin(), extra.end());
  band.insert(band.end(), extra.begin(), extra.end());
  const auto p = run_swum(pick);
  ASSERT_EQ(p.status, 0) << p.output;
  const auto b = run_swum(band);
  ASSERT_EQ(b.status, 0) << b.output;
  const auto picks = nlohmann::json::parse(p.output);
  const auto rows = nlohmann::json::parse(b.output).at("rows");
  ASSERT_EQ(picks.size(), 6u);
  ASSERT_EQ(rows.size(), 6u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& pi = picks.at(i);
    const auto& bi = rows.at(i);
    EXPECT_EQ(pi.at("amplitude_v"), bi.at("amplitude_v"));
    EXPECT_EQ(pi.at("load_n"), bi.at("load_n"));
    ASSERT_TRUE(pi.at("decided").get<bool>() && bi.at("decided").get<bool>()) << pi.dump() << bi.dump();
    EXPECT_EQ(pi.at("frequency_hz").get<double>(), bi.at("frequency_hz").get<double>()) << pi.dump() << bi.dump();
    EXPECT_EQ(pi.at("peak_frequency_hz").get<double>(), bi.at("peak_frequency_hz").get<double>());
    EXPECT_EQ(pi.at("margin_hz").get<double>(), bi.at("margin_hz").get<double>());
    EXPECT_EQ(pi.at("speed_mm_s").get<double>(), bi.at("speed_mm_s").get<double>());
  }
}

TEST(SwumPick, GivesBandsFrequencyForTheSameMotorVoltageLoadAndMargin) {
  expect_pick_equals_band({});
  expect_pick_equals_band({"--margin-hz", "150", "--frequency-hz", "39000:41000:50"});
}

// The refined peak makes the answer hardly depend on the grid: a 50 Hz grid (the old pick default)
// against the default 25 Hz one, within 10 Hz (the vertex of a parabola through the top three points
// of a skewed peak; measured <= 5 Hz on this motor).
TEST(SwumPick, TheOperatingFrequencyHardlyDependsOnTheGrid) {
  const auto fine = run_swum({"pick", "--config", kConfig, "--amplitude-v", "100,300,400", "--json"});
  ASSERT_EQ(fine.status, 0) << fine.output;
  const auto coarse = run_swum(
      {"pick", "--config", kConfig, "--amplitude-v", "100,300,400", "--frequency-hz", "39000:41000:50", "--json"});
  ASSERT_EQ(coarse.status, 0) << coarse.output;
  const auto a = nlohmann::json::parse(fine.output);
  const auto b = nlohmann::json::parse(coarse.output);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a.at(i).at("frequency_hz").get<double>(), b.at(i).at("frequency_hz").get<double>(), 10.0)
        << a.at(i).dump() << b.at(i).dump();
  }
}

}  // namespace
