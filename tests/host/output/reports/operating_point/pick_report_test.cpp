#include "output/reports/operating_point/pick_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

namespace swum::host {
namespace {

// 40 V decided with a naive speed, 60 V decided without one (40.4 kHz outside the sweep),
// 80 V undecided, all at 0 N; 60 V again at 1.5 N (its drift from the lowest decided voltage
// at that load: itself).
std::vector<VoltagePick> picks() {
  PickResult a;
  a.decided = true;
  a.reason = "margin 150 Hz";
  a.frequency_hz = 40150.0;
  a.speed_mm_s = 120.04;
  a.peak_frequency_hz = 40000.0;
  a.margin_hz = 150.0;
  a.naive_speed_mm_s = 100.0;
  PickResult b;
  b.decided = true;
  b.reason = "r2";
  b.frequency_hz = 40050.0;
  b.speed_mm_s = 150.0;
  b.peak_frequency_hz = 39900.0;
  b.margin_hz = 150.0;
  PickResult c;
  c.reason = "no peak";
  return {{40.0, a}, {60.0, b}, {80.0, c}, {60.0, b, 1.5}};
}

TEST(PickGainPercent, IsTheGainOverTheNaiveSpeedOrNaN) {
  EXPECT_NEAR(pick_gain_percent(picks()[0].result), 20.04, 1e-9);
  EXPECT_TRUE(std::isnan(pick_gain_percent(picks()[1].result)));  // no naive speed
  EXPECT_TRUE(std::isnan(pick_gain_percent(picks()[2].result)));  // undecided
}

TEST(PickText, OneLinePerVoltageWithDriftFromTheLowestDecided) {
  EXPECT_EQ(pick_text(picks()),
            "    40 V, 0 N: run at 40150 Hz, 120.0 mm/s (naive 40.4 kHz: 100.0 mm/s, gain +20 %), drift +0 Hz; "
            "margin 150 Hz\n"
            "    60 V, 0 N: run at 40050 Hz, 150.0 mm/s (naive 40.4 kHz: n/a (40.4 kHz outside the sweep)), drift "
            "-100 Hz; r2\n"
            "    80 V, 0 N: undecided: no peak\n"
            "    60 V, 1.5 N: run at 40050 Hz, 150.0 mm/s (naive 40.4 kHz: n/a (40.4 kHz outside the sweep)), drift "
            "+0 Hz; r2\n");
}

TEST(PickJson, NumbersOrNullPerVoltage) {
  const std::string text = pick_json(picks());
  ASSERT_EQ(text.back(), '\n');
  const auto j = nlohmann::json::parse(text);
  ASSERT_EQ(j.size(), 4u);
  EXPECT_DOUBLE_EQ(j[0]["amplitude_v"].get<double>(), 40.0);
  EXPECT_DOUBLE_EQ(j[0]["frequency_hz"].get<double>(), 40150.0);
  EXPECT_NEAR(j[0]["gain_percent"].get<double>(), 20.04, 1e-9);
  EXPECT_DOUBLE_EQ(j[0]["drift_hz"].get<double>(), 0.0);
  EXPECT_TRUE(j[1]["naive_speed_mm_s"].is_null());
  EXPECT_TRUE(j[1]["gain_percent"].is_null());
  EXPECT_DOUBLE_EQ(j[1]["drift_hz"].get<double>(), -100.0);
  EXPECT_EQ(j[2]["decided"], false);
  EXPECT_TRUE(j[2]["frequency_hz"].is_null());
  EXPECT_TRUE(j[2]["drift_hz"].is_null());
  EXPECT_EQ(j[2]["reason"], "no peak");
  EXPECT_DOUBLE_EQ(j[3]["load_n"].get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(j[3]["drift_hz"].get<double>(), 0.0);
  std::vector<std::string> keys;
  const auto ordered = nlohmann::ordered_json::parse(text);
  for (const auto& [key, value] : ordered[0].items()) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{"amplitude_v", "load_n", "decided", "frequency_hz", "speed_mm_s",
                                            "naive_speed_mm_s", "gain_percent", "peak_frequency_hz", "drift_hz",
                                            "margin_hz", "reason"}));
}

TEST(PickScheduleCsv, DecidedVoltagesOnly) {
  EXPECT_EQ(pick_schedule_csv(picks()), "amplitude_v,load_n,frequency_hz\n40,0,40150\n60,0,40050\n60,1.5,40050\n");
  EXPECT_EQ(pick_schedule_csv({}), "amplitude_v,load_n,frequency_hz\n");
}

}  // namespace
}  // namespace swum::host
