#include "output/reports/device/tracking_report.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "formats/number_format.h"

namespace swum::host {
namespace {

std::vector<TrackRunSummary> summaries() {
  TrackRunSummary s;
  s.name = "phase";
  s.blocks = {{30.0, 60.0, 95.5, 12.0, 100.0, 0.955, 150.0}};
  s.min_share = 0.9123;
  s.final_share = 0.955;
  s.final_frequency_hz = 40123.44;
  s.final_margin_hz = 150.06;
  s.final_rise_k = 12.04;
  s.max_rise_k = 13.0;
  return {s};
}

TEST(TrackingText, HeaderAndOneAlignedLinePerRun) {
  EXPECT_EQ(tracking_text(summaries()),
            "run      min share  final share  final frequency (Hz)  final margin (Hz)  final rise (K)\n"
            "phase        0.912        0.955               40123.4              150.1            12.0\n");
}

// The line was printed into 256 bytes: a `--run` name of ~175 characters lost the numbers'
// end and the line break, and the next run's line ran on.
TEST(TrackingText, LongRunNamesAndHugeValuesAreNeverCut) {
  std::vector<TrackRunSummary> runs = summaries();
  runs[0].name = std::string(300, 'r');
  runs.push_back(summaries()[0]);
  runs[1].final_frequency_hz = 1e60;
  const std::string text = tracking_text(runs);
  const std::string header =
      "run      min share  final share  final frequency (Hz)  final margin (Hz)  final rise (K)\n";
  const std::string numbers = "     0.912        0.955               40123.4              150.1            12.0\n";
  const std::string huge = format_number(1e60, "%20.1f");
  EXPECT_EQ(text, header + std::string(300, 'r') + numbers + "phase        0.912        0.955  " + huge +
                      "              150.1            12.0\n");
}

TEST(TrackingJson, FinalValuesAndBlocksPerRun) {
  const std::string text = tracking_json(summaries());
  ASSERT_EQ(text.back(), '\n');
  const auto j = nlohmann::json::parse(text);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0]["run"], "phase");
  EXPECT_DOUBLE_EQ(j[0]["min_share"].get<double>(), 0.9123);
  EXPECT_DOUBLE_EQ(j[0]["max_rise_k"].get<double>(), 13.0);
  ASSERT_EQ(j[0]["blocks"].size(), 1u);
  EXPECT_DOUBLE_EQ(j[0]["blocks"][0]["start_s"].get<double>(), 30.0);
  EXPECT_DOUBLE_EQ(j[0]["blocks"][0]["mean_speed_mm_s"].get<double>(), 95.5);
  EXPECT_DOUBLE_EQ(j[0]["blocks"][0]["best_speed_mm_s"].get<double>(), 100.0);
  EXPECT_DOUBLE_EQ(j[0]["blocks"][0]["mean_rise_k"].get<double>(), 12.0);
  EXPECT_DOUBLE_EQ(j[0]["blocks"][0]["share"].get<double>(), 0.955);
  EXPECT_EQ(tracking_json({}), "[]\n");
}

}  // namespace
}  // namespace swum::host
