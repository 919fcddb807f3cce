#include "output/reports/operating_point/band_report.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace swum::host {
namespace {

std::vector<BandRow> rows() {
  BandRow a;
  a.amplitude_v = 100.0;
  a.load_n = 0.5;
  a.temperature_rise_k = 10.0;
  a.pick.decided = true;
  a.pick.frequency_hz = 40125.5;
  a.pick.speed_mm_s = 80.25;
  a.pick.peak_frequency_hz = 40000.0;
  a.pick.peak_speed_mm_s = 90.0;
  a.pick.margin_hz = 125.5;
  a.pick.collapse_hz = 39950.0;
  a.pick.reason = "margin 125.5 Hz, above the peak";
  BandRow b;
  b.amplitude_v = 200.0;
  b.pick.reason = "no peak, speed still rising";
  return {a, b};
}

BandSummary summary() {
  BandSummary s;
  s.decided = 1;
  s.undecided = 1;
  s.band = FrequencyRange{40125.5, 40125.5};
  s.peak = FrequencyRange{40000.0, 40000.0};
  return s;
}

TEST(BandCsv, OneRowPerChainWithEmptyCellsWhenUndecided) {
  EXPECT_EQ(band_csv(rows()),
            "amplitude_v,load_n,temperature_rise_k,decided,frequency_hz,speed_mm_s,peak_frequency_hz,peak_speed_mm_s,"
            "margin_hz,collapse_hz,reason,current_rms_a_a,current_rms_b_a,current_peak_a_a,current_peak_b_a,"
            "phase_a_deg,phase_b_deg,motional_phase_a_deg,motional_phase_b_deg,power_a_w,power_b_w,"
            "apparent_power_a_va,apparent_power_b_va,power_factor_a,power_factor_b\n"
            "100,0.5,10,1,40125.5,80.25,40000,90,125.5,39950,margin 125.5 Hz; above the peak,,,,,,,,,,,,,,\n"
            "200,0,0,0,,,,,,,no peak; speed still rising,,,,,,,,,,,,,,\n");
}

TEST(BandJson, SummaryThenRowsWithNullWhereUndecided) {
  const std::string text = band_json(rows(), summary(), 100.0);
  ASSERT_EQ(text.back(), '\n');
  const auto j = nlohmann::json::parse(text);
  EXPECT_DOUBLE_EQ(j["min_margin_hz"].get<double>(), 100.0);
  EXPECT_EQ(j["decided"], 1);
  EXPECT_EQ(j["undecided"], 1);
  EXPECT_DOUBLE_EQ(j["band"]["width_hz"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(j["peak"]["low_hz"].get<double>(), 40000.0);
  EXPECT_DOUBLE_EQ(j["rows"][0]["collapse_hz"].get<double>(), 39950.0);
  EXPECT_EQ(j["rows"][0]["reason"], "margin 125.5 Hz, above the peak");  // commas kept in JSON
  EXPECT_TRUE(j["rows"][1]["frequency_hz"].is_null());
  EXPECT_TRUE(j["rows"][1]["margin_hz"].is_null());
  EXPECT_TRUE(j["rows"][1]["collapse_hz"].is_null());
  BandSummary none;
  EXPECT_TRUE(nlohmann::json::parse(band_json({}, none, 100.0))["band"].is_null());
}

TEST(BandText, BandPeakCountsAndUndecidedReasons) {
  EXPECT_EQ(band_text(rows(), summary(), 100.0, "band.csv"),
            "operating band 40126 .. 40126 Hz (0 Hz wide): the picked frequencies, margin >= 100 Hz above the peak\n"
            "peak range 40000 .. 40000 Hz (0 Hz wide)\n"
            "rows: 1 decided, 1 undecided\n"
            "  200 V, 0 N, 0 K rise: no peak, speed still rising\n"
            "rows -> band.csv\n");
  BandSummary none;
  EXPECT_EQ(band_text({}, none, 100.0, ""), "no operating band: no row decided\nrows: 0 decided, 0 undecided\n");
}

}  // namespace
}  // namespace swum::host
