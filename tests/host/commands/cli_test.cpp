// The `swum` command-line contract, exercised on the real binary: JSON fields, CSV
// layout, and one-line errors with the right exit codes for bad input.
#include <gtest/gtest.h>

#include <cstdlib>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "swum_cli_runner.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

using swum::test::CliRun;

CliRun swum(const std::vector<std::string>& args) { return swum::test::run_swum(args); }

const std::string kConfig = swum::test::source_path("config/li2019.toml");

fs::path scratch(const std::string& name) { return swum::test::scratch_path("swum_cli_test", name); }

std::string slurp(const fs::path& path) { return swum::test::read_file(path); }

TEST(SwumCli, NoSubcommandIsAUsageError) {
  const CliRun r = swum({});
  EXPECT_EQ(r.status, 2) << r.output;
}

TEST(SwumCli, ModesJsonHasTheNaturalFrequencies) {
  const CliRun r = swum({"modes", "--config", kConfig, "--json"});
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_NEAR(j.at("f_l1_hz").get<double>(), 39516.0, 0.002 * 39516.0);
  EXPECT_NEAR(j.at("f_b2_hz").get<double>(), 39469.0, 0.002 * 39469.0);
}

// Without --config the commands use the calibrated motor of the data directory (docs/install.md):
// this swum is a build of the checkout, so the checkout's config/li2019.toml.
TEST(SwumCli, WithoutConfigTheDefaultMotorIsUsed) {
  ::unsetenv("SWUM_DATA_DIR");  // an installation's choice in the environment is not this test's
  const CliRun given = swum({"modes", "--config", kConfig, "--json"});
  const CliRun defaulted = swum({"modes", "--json"});
  ASSERT_EQ(defaulted.status, 0) << defaulted.output;
  EXPECT_EQ(defaulted.output, given.output);
  const CliRun literal = swum({"modes", "--config", swum::test::source_path("config/li2019_literal.toml"), "--json"});
  EXPECT_NE(defaulted.output, literal.output);  // the comparison can tell two motors apart
}

TEST(SwumCli, VersionPrintsTheProjectVersion) {
  const CliRun r = swum({"--version"});
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.rfind("swum 0.", 0), 0u) << r.output;
}

TEST(SwumCli, SimulateJsonHasTheContractFields) {
  const CliRun r = swum({"simulate", "--config", kConfig, "--amplitude-v", "400", "--frequency-hz", "40000",
                         "--duration-s", "0.02", "--json"});
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  for (const char* key :
       {"speed_mm_s", "tip_normal_um", "tip_tangential_um", "contact_fraction", "sim_s", "wall_s", "realtime_factor"}) {
    ASSERT_TRUE(j.contains(key)) << key;
    EXPECT_TRUE(j.at(key).is_number()) << key;
  }
  EXPECT_NEAR(j.at("sim_s").get<double>(), 0.02, 1e-6);
  EXPECT_GT(j.at("tip_normal_um").get<double>(), 0.1);
}

TEST(SwumCli, SimulateWholeDurationRunsAllOfIt) {
  const CliRun early = swum({"simulate", "--config", kConfig, "--amplitude-v", "400", "--frequency-hz", "40000",
                             "--duration-s", "0.3", "--json"});
  const CliRun whole = swum({"simulate", "--config", kConfig, "--amplitude-v", "400", "--frequency-hz", "40000",
                             "--duration-s", "0.3", "--whole-duration", "--json"});
  ASSERT_EQ(early.status, 0) << early.output;
  ASSERT_EQ(whole.status, 0) << whole.output;
  const auto e = nlohmann::json::parse(early.output);
  const auto w = nlohmann::json::parse(whole.output);
  EXPECT_LT(e.at("sim_s").get<double>(), 0.1);  // stopped once two windows agreed
  EXPECT_NEAR(w.at("sim_s").get<double>(), 0.3, 1e-6);
  EXPECT_TRUE(w.at("steady").get<bool>());
  EXPECT_NEAR(w.at("speed_mm_s").get<double>(), e.at("speed_mm_s").get<double>(),
              0.01 * e.at("speed_mm_s").get<double>());
}

TEST(SwumCli, SimulateTraceIsACsvWithTimeAndForces) {
  const fs::path trace = scratch("trace.csv");
  const CliRun r = swum({"simulate", "--config", kConfig, "--amplitude-v", "300", "--frequency-hz", "40000",
                         "--duration-s", "0.004", "--trace", trace.string()});
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(trace);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("time_s,q1_m,q1_dot_m_s,q2_m,q2_dot_m_s,tip_normal_um", 0), 0u) << header;
  EXPECT_NE(header.find("normal_force_n,friction_force_n,mover_position_m,mover_velocity_m_s"), std::string::npos);
  int lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  EXPECT_GT(lines, 100);  // 4 ms at ~48 samples per 25 us period
}

TEST(SwumCli, SweepWritesOneRowPerPointAndAPlot) {
  const fs::path csv = scratch("sweep.csv");
  const fs::path png = scratch("sweep.png");
  const CliRun r = swum({"sweep", "--config", kConfig, "--amplitude-v", "200,400", "--frequency-hz", "40000:40400:200",
                         "--jobs", "2", "--out", csv.string(), "--plot", png.string()});
  ASSERT_EQ(r.status, 0) << r.output;
  std::istringstream text(slurp(csv));
  std::string header;
  std::getline(text, header);
  EXPECT_EQ(header.rfind("amplitude_v,frequency_hz,load_n,speed_mm_s,tip_normal_um,tip_tangential_um,status,"
                         "current_a_a,",
                         0),
            0u)
      << header;
  EXPECT_NE(header.find(",current_rms_a_a,"), std::string::npos) << header;
  std::vector<std::string> rows;
  for (std::string line; std::getline(text, line);) rows.push_back(line);
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0].rfind("200,40000,0,", 0), 0u) << rows[0];
  EXPECT_EQ(rows[5].rfind("400,40400,0,", 0), 0u) << rows[5];
  EXPECT_GT(fs::file_size(png), 1000u);
}

struct BadArguments {
  std::vector<std::string> args;
  int status;
  std::string message_part;
};

// Printed as the command line, so the ctest names are readable and the same on every build.
void PrintTo(const BadArguments& b, std::ostream* os) {
  for (const std::string& arg : b.args) *os << (arg.find('/') == std::string::npos ? arg : "PATH") << ' ';
  *os << "-> " << b.status;
}

class SwumCliRejects : public ::testing::TestWithParam<BadArguments> {};

TEST_P(SwumCliRejects, WithOneLineNamingTheProblem) {
  const CliRun r = swum(GetParam().args);
  EXPECT_EQ(r.status, GetParam().status) << r.output;
  EXPECT_NE(r.output.find(GetParam().message_part), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("swum: error: "), 0u) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

INSTANTIATE_TEST_SUITE_P(
    BadInput, SwumCliRejects,
    ::testing::Values(
        BadArguments{
            {"simulate", "--config", kConfig, "--amplitude-v", "nan", "--frequency-hz", "40000"}, 2, "--amplitude-v"},
        BadArguments{
            {"simulate", "--config", kConfig, "--amplitude-v", "100", "--frequency-hz", "4e4x"}, 2, "--frequency-hz"},
        BadArguments{
            {"simulate", "--config", kConfig, "--amplitude-v", "-5", "--frequency-hz", "40000"}, 2, "--amplitude-v"},
        BadArguments{
            {"simulate", "--config", kConfig, "--amplitude-v", "100", "--frequency-hz", "inf"}, 2, "--frequency-hz"},
        BadArguments{{"simulate", "--config", kConfig, "--amplitude-v", "100", "--frequency-hz", "40000",
                      "--drive-phase-deg", "400"},
                     2,
                     "--drive-phase-deg"},
        BadArguments{{"simulate", "--config", "/nonexistent/m.toml", "--amplitude-v", "100", "--frequency-hz", "40000"},
                     1,
                     "/nonexistent/m.toml"},
        BadArguments{{"simulate", "--amplitude-v", "100", "--frequency-hz", "40000", "--config"}, 2, "--config"},
        BadArguments{{"sweep", "--config", kConfig, "--amplitude-v", "100,,200", "--frequency-hz", "40000", "--out",
                      "/tmp/x.csv"},
                     2,
                     "--amplitude-v"},
        BadArguments{{"sweep", "--config", kConfig, "--amplitude-v", "100", "--frequency-hz", "41000:40000:100",
                      "--out", "/tmp/x.csv"},
                     2,
                     "--frequency-hz"},
        BadArguments{{"sweep", "--config", kConfig, "--amplitude-v", "100", "--frequency-hz", "40000", "--out",
                      "/nonexistent/x.csv"},
                     1,
                     "/nonexistent/x.csv"},
        BadArguments{{"modes", "--config", kConfig, "--bogus"}, 2, "--bogus"}));

TEST(SwumCli, ConfigErrorsNameFileAndKey) {
  const fs::path bad = scratch("bad.toml");
  std::ofstream(bad) << "[contact]\npreload_n = -3\n";
  CliRun r = swum({"modes", "--config", bad.string()});
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find(bad.string()), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("preload_n"), std::string::npos) << r.output;

  std::ofstream(bad) << "[contact]\nno_such_key = 1\n";
  r = swum({"modes", "--config", bad.string()});
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("no_such_key"), std::string::npos) << r.output;
}

}  // namespace
