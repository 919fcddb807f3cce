#include "output/reports/fit/calibration_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

namespace swum::host {
namespace {

// Two free parameters (one identified, one not), one fact that holds after the fit, one push
// and one front: every part of the reports has something to show.
CalibrationResult small_result() {
  CalibrationResult r;
  r.selection = {{"stator.zeta1", 0.25, true, ""}, {"contact.mu", 3.5, false, "expected SE above 1 spread"}};
  CalibratedParameter zeta{"stator.zeta1", "1", 0.01, 0.002, 0.0125, 0.0004, 0.001, 0.1, true, false, ""};
  CalibratedParameter mu{
      "contact.mu",    "1", 0.2, 0.05, 0.2, std::numeric_limits<double>::infinity(), 0.05, 1.0, false, false,
      "flat direction"};
  r.parameters = {zeta, mu};
  r.correlations = {{1.0}};
  r.held_out_points = 4;
  r.operating_points = 16;
  r.noise = 0.01;
  r.noise_source = "repeats";
  r.train_rms_prior = 0.2;
  r.train_rms = 0.02;
  r.held_out_rms_prior = 0.25;
  r.held_out_rms = 0.03;
  r.held_out_evidence.p_value = 0.001;
  r.facts = {{"peak", "Hz", 39000.0, 41000.0, 40000.0, 39500.0, std::nan(""), false, true, false}};
  r.explored = {{"stator.zeta1", 0.013}};
  r.reach = {{"peak", true, 39900.0, {"speed", "stall"}}};
  FactFront front;
  front.first = "peak";
  front.second = "speed";
  front.weights = {1.0, 10.0};
  front.first_values = {40500.0, 39900.0};
  front.second_values = {120.0, 110.0};
  front.first_misses = {0.5, 0.0};
  front.second_misses = {0.0, 0.2};
  r.fronts = {front};
  r.rounds = 2;
  r.starts_run = 5;
  r.model_evaluations = 321;
  r.conclusion = "fitted: stator.zeta1";
  return r;
}

TEST(CalibrationJson, CarriesEveryPartWithNullForTheUnknown) {
  const std::string text = calibration_json(small_result(), true, 1.5);
  ASSERT_EQ(text.back(), '\n');
  const auto j = nlohmann::json::parse(text);
  ASSERT_EQ(j["parameters"].size(), 2u);
  EXPECT_EQ(j["parameters"][0]["name"], "stator.zeta1");
  EXPECT_DOUBLE_EQ(j["parameters"][0]["value"].get<double>(), 0.0125);
  EXPECT_DOUBLE_EQ(j["parameters"][0]["standard_error"].get<double>(), 0.0004);
  EXPECT_EQ(j["parameters"][0]["bounds"], nlohmann::json::array({0.001, 0.1}));
  EXPECT_TRUE(j["parameters"][1]["standard_error"].is_null());  // +inf: not identifiable
  EXPECT_EQ(j["parameters"][1]["reason"], "flat direction");
  EXPECT_EQ(j["selection"][1]["selected"], false);
  EXPECT_EQ(j["correlations"]["names"], nlohmann::json::array({"stator.zeta1"}));
  EXPECT_EQ(j["measurements"]["held_out_points"], 4);
  EXPECT_DOUBLE_EQ(j["measurements"]["held_out_p_value"].get<double>(), 0.001);
  EXPECT_TRUE(j["facts"][0]["explored_value"].is_null());  // NaN
  EXPECT_EQ(j["facts"][0]["band"], nlohmann::json::array({39000.0, 41000.0}));
  EXPECT_DOUBLE_EQ(j["explored"]["stator.zeta1"].get<double>(), 0.013);
  EXPECT_EQ(j["reach"][0]["breaks"], nlohmann::json::array({"speed", "stall"}));
  EXPECT_DOUBLE_EQ(j["fronts"][0]["points"][1]["weight"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(j["fronts"][0]["points"][1]["second_miss"].get<double>(), 0.2);
  EXPECT_EQ(j["rounds"], 2);
  EXPECT_EQ(j["starts"], 5);
  EXPECT_EQ(j["model_evaluations"], 321);
  EXPECT_EQ(j["conclusion"], "fitted: stator.zeta1");
  EXPECT_DOUBLE_EQ(j["wall_s"].get<double>(), 1.5);
  // The keys in the order the files have always had.
  std::vector<std::string> keys;
  const auto ordered = nlohmann::ordered_json::parse(text);
  for (const auto& [key, value] : ordered.items()) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"parameters", "selection", "correlations", "measurements", "facts",
                                            "explored", "reach", "fronts", "rounds", "starts", "model_evaluations",
                                            "conclusion", "wall_s"}));
}

TEST(CalibrationJson, LeavesOutMeasurementsWithoutAMeasuredSweep) {
  const auto j = nlohmann::json::parse(calibration_json(small_result(), false, 0.0));
  EXPECT_FALSE(j.contains("measurements"));
}

TEST(CalibrationSummaryText, ListsEachPartOnItsOwnLine) {
  EXPECT_EQ(calibration_summary_text(small_result(), true),
            "free set (Fisher information at the prior):\n"
            "  stator.zeta1: selected\n"
            "  contact.mu: expected SE above 1 spread\n"
            "parameters:\n"
            "  stator.zeta1                       0.0125       +- 0.0004    1 (prior 0.01)\n"
            "  contact.mu                         not identifiable: flat direction\n"
            "training RMS 20 % -> 2 %; held-out RMS 25 % -> 3 % on 4 of 16 operating points (noise estimate 1 %, "
            "repeats)\n"
            "fact peak: 40000 -> 39500 Hz (band 39000..41000) holds; every free parameter moving: n/a fails\n"
            "first fit, every free parameter moving: stator.zeta1 = 0.013\n"
            "pushed peak: holds at 39900; then lose (miss grows): speed, stall\n"
            "front peak vs speed (weight: first, second):\n"
            "  1: 40500, 120\n"
            "  10: 39900, 110\n"
            "conclusion: fitted: stator.zeta1\n");
}

// A reason longer than any line buffer comes out whole, newline included.
TEST(CalibrationSummaryText, ALongReasonIsNeverCut) {
  CalibrationResult r = small_result();
  const std::string reason(700, 'x');
  r.parameters[1].reason = reason;
  const std::string text = calibration_summary_text(r, true);
  EXPECT_NE(text.find("  contact.mu                         not identifiable: " + reason + "\ntraining RMS"),
            std::string::npos);
}

TEST(CalibrationReportMarkdown, HasTheCommandTablesAndFooter) {
  const std::string md = calibration_report_markdown("--config m.toml --facts f.toml", nullptr, small_result(), {},
                                                     2.5);
  EXPECT_EQ(md.rfind("# Calibration report\n\n`swum calibrate --config m.toml --facts f.toml`\n\n**Conclusion:** "
                     "fitted: stator.zeta1\n\n",
                     0),
            0u);
  EXPECT_NE(md.find("| `stator.zeta1` | 0.25 | selected |\n"), std::string::npos);
  EXPECT_NE(md.find("| `stator.zeta1` | 0.01 | 0.0125 | 0.0004 | 1 | identified |\n"), std::string::npos);
  EXPECT_NE(md.find("| `contact.mu` | 0.2 | 0.2 | inf | 1 | flat direction |\n"), std::string::npos);
  EXPECT_NE(md.find("| `stator.zeta1` | +1.00 |\n"), std::string::npos);
  EXPECT_EQ(md.find("## Measurements"), std::string::npos);  // no measured sweep
  EXPECT_NE(md.find("| peak | 39000 .. 41000 Hz | 40000 | 39500 | yes | n/a | **no** |\n"), std::string::npos);
  EXPECT_NE(md.find("Pushed to hold (weight 100): **peak** holds at 39900; then these lose (their miss grows): "
                    "speed, stall."),
            std::string::npos);
  EXPECT_NE(md.find("| 10 | 39900 | 110 |\n"), std::string::npos);
  EXPECT_TRUE(md.ends_with("\n\n2 rounds, 5 starts, 321 model evaluations, 2.5 s.\n")) << md;
}

TEST(CalibrationReportMarkdown, ShowsTheMeasuredFitAndItsPlots) {
  MeasurementSet set;
  const std::string md = calibration_report_markdown("--config m.toml --measured s.csv", &set, small_result(),
                                                     {"speed_load_0N.png"}, 1.0);
  EXPECT_NE(md.find("| prior | 20 % | 25 % |\n| calibrated | 2 % | 3 % |\n\n4 of 16 operating points held out; noise "
                    "estimate 1 % (repeats).\n"),
            std::string::npos);
  EXPECT_NE(md.find("![speed_load_0N.png](speed_load_0N.png)\n"), std::string::npos);
}

TEST(CalibrationFittedHeader, NamesTheCommandAndEachParameter) {
  EXPECT_EQ(calibration_fitted_header("--config m.toml --facts f.toml", small_result()),
            "# Written by `swum calibrate --config m.toml --facts f.toml`: fitted: stator.zeta1\n"
            "#   stator.zeta1 = 0.0125 +- 0.0004 1 (prior 0.01)\n"
            "#   contact.mu = 0.2 1, not identifiable: flat direction\n");
}

}  // namespace
}  // namespace swum::host
