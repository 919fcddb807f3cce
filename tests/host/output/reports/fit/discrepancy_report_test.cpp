#include "output/reports/fit/discrepancy_report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

namespace swum::host {
namespace {

HeldOutEvidence evidence() {
  HeldOutEvidence e;
  e.points = 15;
  e.improved = 14;
  e.signed_rank = 119.0;
  e.signed_rank_p = 6.1e-05;
  e.sign_flip_p = 0.0002;
  e.p_value = 0.00012;
  e.rms_before = 0.2;
  e.rms_after = 0.05;
  e.reduction = 0.75;
  e.reduction_low = 0.6;
  e.reduction_high = 0.85;
  return e;
}

// One round that names `preload` after skipping `thermal`; the speed gap shrinks.
DiscrepancyResult small_result() {
  DiscrepancyResult r;
  r.baseline_map.summary = "structured: speed grows with load";
  r.baseline_map.rms = 0.2;
  r.baseline_map.noise = 0.01;
  r.baseline_map.noise_source = "repeats";
  r.baseline_map.structured = true;
  r.augmented_map.summary = "within the noise";
  DiscrepancyRound round;
  round.candidates = {{"preload", false, "", 2.5, 0.04, 0.05, -725.0}, {"thermal", true, "no time column"}};
  round.fitted = 0;
  round.accepted = true;
  round.held_out = evidence();
  round.fitted_delta_bic = -725.0;
  round.verdict = "named preload";
  r.rounds = {round};
  r.effects = {{"preload", "force_n", "N", 2.5, 0.12, -725.0, evidence()}};
  r.held_out_points = 15;
  r.operating_points = 60;
  r.rms_before = 0.2;
  r.rms_after = 0.05;
  r.gaps[static_cast<std::size_t>(Quantity::speed)] = {15, 0.2, 0.5, 0.05, 0.1};
  r.conclusion = "the model misses preload";
  r.model_evaluations = 42;
  return r;
}

TEST(DiscrepancyJson, CarriesEffectsRoundsGapsAndBaseline) {
  const std::string text = discrepancy_json(small_result(), 3.0);
  ASSERT_EQ(text.back(), '\n');
  const auto j = nlohmann::json::parse(text);
  ASSERT_EQ(j["effects"].size(), 1u);
  EXPECT_EQ(j["effects"][0]["name"], "preload");
  EXPECT_DOUBLE_EQ(j["effects"][0]["parameters"]["force_n"]["value"].get<double>(), 2.5);
  EXPECT_EQ(j["effects"][0]["parameters"]["force_n"]["unit"], "N");
  EXPECT_EQ(j["effects"][0]["held_out"]["improved"], 14);
  EXPECT_EQ(j["effects"][0]["held_out"]["reduction_interval_90"], nlohmann::json::array({0.6, 0.85}));
  EXPECT_EQ(j["held_out_points"], 15);
  EXPECT_EQ(j["operating_points"], 60);
  ASSERT_TRUE(j["gaps"].contains("speed_mm_s"));
  EXPECT_FALSE(j["gaps"].contains("tip_normal_um"));  // no held-out values of it
  EXPECT_DOUBLE_EQ(j["gaps"]["speed_mm_s"]["max_before"].get<double>(), 0.5);
  EXPECT_EQ(j["baseline"]["noise_source"], "repeats");
  EXPECT_EQ(j["rounds"][0]["fitted"], "preload");
  EXPECT_EQ(j["rounds"][0]["named"], true);
  EXPECT_DOUBLE_EQ(j["rounds"][0]["candidates"][0]["delta_bic"].get<double>(), -725.0);
  EXPECT_EQ(j["rounds"][0]["candidates"][1]["note"], "no time column");
  EXPECT_FALSE(j["rounds"][0]["candidates"][1].contains("value"));  // skipped: no scores
  EXPECT_EQ(j["conclusion"], "the model misses preload");
  EXPECT_EQ(j["model_evaluations"], 42);
  EXPECT_DOUBLE_EQ(j["wall_s"].get<double>(), 3.0);
}

TEST(DiscrepancySummaryText, ShowsRoundsEffectsAndGap) {
  EXPECT_EQ(discrepancy_summary_text(small_result()),
            "baseline: structured: speed grows with load\n"
            "round 1: named preload\n"
            "  preload          value 2.5        train RMS 4 %      held-out RMS 5 %      dBIC -725.0\n"
            "  thermal          skipped: no time column\n"
            "named effect: preload  force_n = 2.5 +- 0.12 N\n"
            "    evidence: delta BIC -725.0; 14 of 15 held-out points better (p 0.00012: signed-rank 6.1e-05, "
            "sign-flip 0.0002); held-out RMS 20 % -> 5 %, reduction 75 % (90 % interval 60..85 %)\n"
            "held-out gap (relative RMS / max): 20 % -> 5 %\n"
            "  speed_mm_s         RMS 20 %     -> 5 %      max 50 %     -> 10 %\n"
            "conclusion: the model misses preload\n");
}

TEST(DiscrepancyReportMarkdown, HasInputsSelectionEffectsAndGap) {
  MeasurementSet set;
  const std::string md = discrepancy_report_markdown("--config m.toml --measured s.csv", set, small_result(),
                                                     {"speed_mm_s.png"});
  EXPECT_EQ(md.rfind("# Model discrepancy report\n\n`swum discrepancy --config m.toml --measured s.csv`\n\n"
                     "**Conclusion:** the model misses preload\n\n",
                     0),
            0u);
  EXPECT_NE(md.find("| preload | 2.5 | 4 % | 5 % | -725.0 |\n| thermal | skipped: no time column | | | |\n"),
            std::string::npos);
  EXPECT_NE(md.find("- **preload**: `force_n = 2.5` +- 0.12 N; evidence: delta BIC -725.0;"), std::string::npos);
  EXPECT_NE(md.find("Named when both hold: delta BIC on the 45 training points"), std::string::npos);
  EXPECT_NE(md.find("| speed_mm_s | 15 | 20 % | 5 % | 50 % | 10 % |\n| all | | 20 % | 5 % | | |\n"), std::string::npos);
  EXPECT_NE(md.find("Remaining residual: within the noise\n\n![speed_mm_s.png](speed_mm_s.png)\n"), std::string::npos);
  EXPECT_TRUE(md.ends_with("\nAugmented config: `augmented.toml`. 42 model evaluations of every point.\n")) << md;
}

TEST(DiscrepancyAugmentedHeader, NamesEachEffectOrSaysNone) {
  DiscrepancyResult r = small_result();
  EXPECT_EQ(discrepancy_augmented_header("--config m.toml --measured s.csv", r),
            "# Written by `swum discrepancy --config m.toml --measured s.csv`: the baseline plus the named effects and "
            "any change of the base model it found.\n"
            "#   effects.preload.force_n = 2.5 +- 0.12 N\n");
  r.effects.clear();
  EXPECT_EQ(discrepancy_augmented_header("--config m.toml --measured s.csv", r),
            "# Written by `swum discrepancy --config m.toml --measured s.csv`: the baseline plus the named effects and "
            "any change of the base model it found.\n"
            "#   no effect named: identical to the baseline\n");
}

TEST(DiscrepancyPlots, OnePngPerMeasuredQuantity) {
  MeasurementSet set;
  set.has_quantity[static_cast<std::size_t>(Quantity::speed)] = true;
  DiscrepancyResult r = small_result();
  for (int i = 0; i < 3; ++i) {
    Measurement m;
    m.amplitude_v = 100.0;
    m.frequency_hz = 40000.0 + 100.0 * i;
    m.values[static_cast<std::size_t>(Quantity::speed)] = 50.0 + i;
    set.rows.push_back(m);
    PredictedPoint p;
    p.ok = true;
    p.values[static_cast<std::size_t>(Quantity::speed)] = 49.0 + i;
    r.baseline_predictions.push_back(p);
    r.augmented_predictions.push_back(p);
  }
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "discrepancy_report_plots";
  std::filesystem::create_directories(dir);
  EXPECT_EQ(write_discrepancy_plots(dir, set, r), (std::vector<std::string>{"speed_mm_s.png"}));
  EXPECT_GT(std::filesystem::file_size(dir / "speed_mm_s.png"), 0u);
}

}  // namespace
}  // namespace swum::host
