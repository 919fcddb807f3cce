#include "output/reports/model/stator_report.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace swum::host {
namespace {

ModeBranch branch(double amplitude_um, bool stable) {
  ModeBranch b;
  b.tip_amplitude_um = amplitude_um;
  b.stable = stable;
  return b;
}

// One point with two normal branches and one tangential branch; an up-sweep follows the
// second normal branch.
std::vector<SweepPoint> sweep() {
  SweepPoint p;
  p.response.amplitude_v = 100.0;
  p.response.frequency_hz = 40000.5;
  p.response.normal.branches = {branch(2.5, false), branch(1.25, true)};
  p.response.tangential.branches = {branch(0.75, true)};
  p.followed_normal = 1;
  p.followed_tangential = 0;
  return {p};
}

TEST(StatorRows, OneRowPerPairOfBranchesWithTheFollowedOneMarked) {
  const std::vector<StatorRow> rows = stator_rows(sweep());
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].branch, 0);
  EXPECT_EQ(rows[0].normal_branch, 0);
  EXPECT_FALSE(rows[0].stable());
  EXPECT_FALSE(rows[0].followed);
  EXPECT_EQ(rows[1].branch, 1);
  EXPECT_EQ(rows[1].normal_branch, 1);
  EXPECT_EQ(rows[1].tangential_branch, 0);
  EXPECT_TRUE(rows[1].stable());
  EXPECT_TRUE(rows[1].followed);
  EXPECT_DOUBLE_EQ(rows[1].tip_normal_um, 1.25);
  EXPECT_DOUBLE_EQ(rows[1].tip_tangential_um, 0.75);
}

TEST(StatorCsv, FixedDigitsPerColumn) {
  EXPECT_EQ(stator_csv(stator_rows(sweep())), "amplitude_v,frequency_hz,branch,stable,tip_normal_um,tip_tangential_um\n"
                                              "100,40000.5,0,0,2.500000,0.750000\n"
                                              "100,40000.5,1,1,1.250000,0.750000\n");
  EXPECT_EQ(stator_backbone_csv({{100.0, 40100.25, 3.5, 39900.0, 1.0}}),
            "amplitude_v,normal_peak_hz,normal_peak_um,tangential_peak_hz,tangential_peak_um\n"
            "100,40100.250,3.500000,39900.000,1.000000\n");
}

TEST(StatorJson, RowsWithEveryBranchFlagAndTheBackbone) {
  const std::string text = stator_json(stator_rows(sweep()), {{100.0, 40100.25, 3.5, 39900.0, 1.0}});
  ASSERT_EQ(text.back(), '\n');
  const auto j = nlohmann::json::parse(text);
  ASSERT_EQ(j["rows"].size(), 2u);
  EXPECT_EQ(j["rows"][1]["stable"], true);
  EXPECT_EQ(j["rows"][1]["followed_by_up_sweep"], true);
  EXPECT_EQ(j["rows"][0]["normal_stable"], false);
  EXPECT_EQ(j["rows"][0]["tangential_stable"], true);
  EXPECT_DOUBLE_EQ(j["rows"][0]["frequency_hz"].get<double>(), 40000.5);
  ASSERT_EQ(j["backbone"].size(), 1u);
  EXPECT_DOUBLE_EQ(j["backbone"][0]["normal_peak_hz"].get<double>(), 40100.25);
  EXPECT_DOUBLE_EQ(j["backbone"][0]["tangential_peak_um"].get<double>(), 1.0);
}

}  // namespace
}  // namespace swum::host
