// `swum band` on the real binary: the CSV and JSON layouts on a coarse grid, and the one-line
// errors (option, file) with their exit statuses.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "swum_cli_runner.h"
#include "test_paths.h"

namespace {

using swum::test::run_swum;
const std::string kConfig = swum::test::source_path("config/li2019.toml");
const std::string kThermalConfig = swum::test::source_path("config/li2019_thermal.toml");

TEST(SwumBand, WritesTheRowsAndPrintsTheBand) {
  const auto out = swum::test::scratch_path("band", "band.csv");
  std::filesystem::remove(out);
  auto r = run_swum({"band", "--config", kConfig, "--amplitude-v", "100,400", "--frequency-hz", "39000:40500:50",
                     "--out", out.string(), "--jobs", "2"});
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.rfind("operating band 39546 .. 40395 Hz (849 Hz wide)", 0), 0u) << r.output;
  EXPECT_NE(r.output.find("rows: 2 decided, 0 undecided\n"), std::string::npos) << r.output;
  const std::string csv = swum::test::read_file(out);
  EXPECT_EQ(
      csv.substr(0, csv.find('\n') + 1),
      "amplitude_v,load_n,temperature_rise_k,decided,frequency_hz,speed_mm_s,peak_frequency_hz,peak_speed_mm_s,"
      "margin_hz,collapse_hz,reason,current_rms_a_a,current_rms_b_a,current_peak_a_a,current_peak_b_a,phase_a_deg,"
      "phase_b_deg,motional_phase_a_deg,motional_phase_b_deg,power_a_w,power_b_w,apparent_power_a_va,"
      "apparent_power_b_va,power_factor_a,power_factor_b\n");
  EXPECT_NE(csv.find("\n100,0,0,1,40395,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n400,0,0,1,39546,"), std::string::npos) << csv;
  EXPECT_FALSE(std::filesystem::exists(out.string() + ".tmp"));
}

TEST(SwumBand, JsonHasTheSummaryAndTheRowsOverTemperatureRises) {
  auto r = run_swum({"band", "--config", kThermalConfig, "--amplitude-v", "400", "--temperature-rise-k", "0,50",
                     "--frequency-hz", "38750:40000:50", "--json"});
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j.at("decided"), 2);
  EXPECT_EQ(j.at("undecided"), 0);
  EXPECT_EQ(j.at("min_margin_hz"), 100.0);
  const auto& rows = j.at("rows");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].at("temperature_rise_k"), 0.0);
  EXPECT_EQ(rows[1].at("temperature_rise_k"), 50.0);
  for (const char* key : {"amplitude_v", "load_n", "frequency_hz", "speed_mm_s", "peak_frequency_hz", "peak_speed_mm_s",
                          "margin_hz", "collapse_hz"}) {
    EXPECT_TRUE(rows[1].at(key).is_number()) << key;
  }
  EXPECT_GT(rows[0].at("peak_frequency_hz").get<double>() - rows[1].at("peak_frequency_hz").get<double>(), 200.0);
  EXPECT_EQ(j.at("band").at("low_hz"), rows[1].at("frequency_hz"));
  EXPECT_EQ(j.at("band").at("high_hz"), rows[0].at("frequency_hz"));
  EXPECT_EQ(j.at("peak").at("low_hz"), rows[1].at("peak_frequency_hz"));
}

TEST(SwumBand, AnUndecidedRowIsReportedAndFailsTheRun) {
  auto r = run_swum({"band", "--config", kConfig, "--amplitude-v", "100", "--frequency-hz", "39000:40000:50"});
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("no operating band: no row decided\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("100 V, 0 N, 0 K rise: speed is highest at the top of the sweep"), std::string::npos);
  EXPECT_NE(r.output.find("swum: error: 1 of 1 rows undecided: the band may not cover them (see reason)\n"),
            std::string::npos)
      << r.output;
}

struct BadBand {
  std::vector<std::string> args;
  int status;
  std::string message;  // the whole output: one line
};

void PrintTo(const BadBand& b, std::ostream* os) {
  for (const std::string& arg : b.args) *os << (arg.find('/') == std::string::npos ? arg : "PATH") << ' ';
  *os << "-> " << b.status;
}

class SwumBandRejects : public ::testing::TestWithParam<BadBand> {};

TEST_P(SwumBandRejects, WithOneLineNamingTheProblem) {
  const auto out = swum::test::scratch_path("band", "refused.csv");
  std::filesystem::remove(out);
  std::vector<std::string> args = {"band", "--out", out.string()};
  args.insert(args.end(), GetParam().args.begin(), GetParam().args.end());
  const auto r = run_swum(args);
  EXPECT_EQ(r.status, GetParam().status) << r.output;
  EXPECT_EQ(r.output, GetParam().message);
  EXPECT_FALSE(std::filesystem::exists(out)) << "nothing written on refusal";
}

INSTANTIATE_TEST_SUITE_P(
    BadInput, SwumBandRejects,
    ::testing::Values(BadBand{{"--config", kConfig, "--amplitude-v", "100,x"},
                              2,
                              "swum: error: --amplitude-v: 'x' is not a number\n"},
                      BadBand{{"--config", kConfig, "--amplitude-v", "100", "--load", "0,,1"},
                              2,
                              "swum: error: --load: empty entry in list '0,,1'\n"},
                      BadBand{{"--config", kConfig, "--amplitude-v", "100", "--temperature-rise-k", "0,50"},
                              2,
                              "swum: error: --temperature-rise-k: 50 K needs the thermal effect, but " + kConfig +
                                  " has [effects.thermal] enabled = false\n"},
                      BadBand{{"--config", kThermalConfig, "--amplitude-v", "100", "--temperature-rise-k", "nan"},
                              2,
                              "swum: error: --temperature-rise-k: 'nan' is not finite\n"},
                      BadBand{{"--config", kThermalConfig, "--amplitude-v", "100", "--temperature-rise-k", "500"},
                              2,
                              "swum: error: --temperature-rise-k: 500 is outside 0..300 K\n"},
                      BadBand{{"--config", kConfig, "--amplitude-v", "100", "--margin-hz", "-5"},
                              2,
                              "swum: error: --margin-hz: must be within 0..10000\n"},
                      BadBand{{"--config", kConfig, "--amplitude-v", "100", "--frequency-hz", "40500:39000:50"},
                              2,
                              "swum: error: --frequency-hz: STOP in '40500:39000:50' is below START\n"},
                      BadBand{{"--config", kConfig, "--amplitude-v", "100", "--jobs", "-1"},
                              2,
                              "swum: error: --jobs: must be within 0..1024 (0 = all cores)\n"},
                      BadBand{{"--config", kConfig, "--amplitude-v", "100", "--bogus"},
                              2,
                              "swum: error: The following argument was not expected: --bogus (see swum --help)\n"},
                      BadBand{{"--config", "/nonexistent/motor.toml", "--amplitude-v", "100"},
                              1,
                              "swum: error: cannot read /nonexistent/motor.toml: No such file or directory\n"}));

}  // namespace
