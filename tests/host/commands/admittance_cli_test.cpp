// `swum admittance` on the real binary: the JSON and CSV layouts and the plots on a coarse grid,
// and one-line errors with a non-zero status on bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "swum_cli_runner.h"
#include "test_paths.h"

namespace {

using swum::test::run_swum;
const std::string kConfig = swum::test::source_path("config/li2019.toml");

TEST(SwumAdmittance, JsonHasTheAnalyticAndTheFittedCircuitPerLevel) {
  const auto csv = swum::test::scratch_path("admittance", "admittance.csv");
  const auto plots = swum::test::scratch_path("admittance", "plots");
  std::filesystem::remove(csv);
  std::filesystem::remove_all(plots);
  auto r = run_swum({"admittance", "--config", kConfig, "--amplitude-v", "1,200", "--frequency-hz", "38000:41000:100",
                     "--driven-phase", "b", "--json", "--csv", csv.string(), "--plot-dir", plots.string()});
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j.at("phase"), "b");
  EXPECT_EQ(j.at("mounting"), "free");
  EXPECT_NEAR(j.at("analytic").at("circuit").at("clamped_capacitance_nf").get<double>(), 10.0, 1e-9);
  EXPECT_NEAR(j.at("analytic").at("derived").at("L1").at("series_resonance_hz").get<double>(), 39516.0, 0.1);
  ASSERT_EQ(j.at("levels").size(), 2u);
  const auto& small = j.at("levels").at(0);
  EXPECT_EQ(small.at("amplitude_v"), 1.0);
  EXPECT_TRUE(small.at("fit_ok").get<bool>());
  EXPECT_EQ(small.at("points").size(), 31u);
  const double r_fit = small.at("circuit").at("B2").at("motional_resistance_ohm").get<double>();
  const double r_analytic = j.at("analytic").at("circuit").at("B2").at("motional_resistance_ohm").get<double>();
  EXPECT_NEAR(r_fit / r_analytic, 1.0, 0.01);
  EXPECT_GT(small.at("standard_error").at("B2").at("motional_resistance_ohm").get<double>(), 0.0);
  EXPECT_FALSE(small.at("points").at(0).at("diverged").get<bool>());
  EXPECT_GT(small.at("points").at(0).at("current_a").get<double>(), 0.0);
  const std::string table = swum::test::read_file(csv);
  EXPECT_EQ(table.substr(0, table.find('\n') + 1),
            "amplitude_v,frequency_hz,magnitude_siemens,phase_deg,conductance_siemens,susceptance_siemens,current_a,"
            "diverged\n");
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 1 + 2 * 31);
  for (const char* name : {"admittance_magnitude.png", "admittance_phase.png", "admittance_circle.png"}) {
    EXPECT_GT(std::filesystem::file_size(plots / name), 1000u) << name;
  }
}

TEST(SwumAdmittance, TextShowsBothCircuits) {
  auto r = run_swum({"admittance", "--config", kConfig, "--frequency-hz", "38000:41000:100"});
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("Admittance of phase a, free"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("  R_m (ohm)    3381.05  "), std::string::npos) << r.output;
}

TEST(SwumAdmittance, TheRetiredPhaseOptionPointsToDrivenPhase) {
  const auto r = run_swum({"admittance", "--config", kConfig, "--phase", "b"});
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_NE(r.output.find("swum admittance: --phase was renamed --driven-phase ("), std::string::npos) << r.output;
}

TEST(SwumAdmittance, BadInputIsOneLineAndANonZeroStatus) {
  const std::vector<std::vector<std::string>> bad = {{"--amplitude-v", "-1"},
                                                     {"--amplitude-v", "0"},
                                                     {"--amplitude-v", "abc"},
                                                     {"--frequency-hz", "41000:38000:100"},
                                                     {"--frequency-hz", "39000:39100:50"},
                                                     {"--frequency-hz", ""},
                                                     {"--driven-phase", "c"},
                                                     {"--mounting", "loose"}};
  for (const auto& args : bad) {
    std::vector<std::string> command = {"admittance", "--config", kConfig};
    command.insert(command.end(), args.begin(), args.end());
    const auto r = run_swum(command);
    SCOPED_TRACE(args.front() + " " + args.back());
    EXPECT_NE(r.status, 0);
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find(args.front()), std::string::npos) << r.output;
  }
}

}  // namespace
