// `swum stator` and `swum identify` on the real binary: CSV/JSON layout, the round trip from
// library-generated amplitudes, and one-line errors (file, line, column) with exit codes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/free_stator/synthetic_amplitudes.h"
#include "formats/parameter_file.h"
#include "output/amplitude_csv.h"
#include "swum_cli_runner.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

using swum::test::CliRun;

CliRun swum_run(const std::vector<std::string>& args) { return swum::test::run_swum(args); }

const std::string kLiteral = swum::test::source_path("config/li2019_literal.toml");

fs::path scratch(const std::string& name) { return swum::test::scratch_path("swum_hb_cli_test", name); }

std::string slurp(const fs::path& path) { return swum::test::read_file(path); }

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

fs::path synthetic_csv(const std::string& name, const swum::MotorParameters& truth) {
  swum::SyntheticAmplitudeOptions so;
  so.relative_noise = 0.02;
  so.seed = 5;
  // The paper's 50..365 Vpp on the literal reading (model_spec §0): terminal amplitudes of half.
  const std::vector<double> v = {25, 42.5, 60, 77.5, 95, 112.5, 130, 147.5, 165, 182.5};
  const std::vector<double> f = {39250.0, 39500.0, 39750.0};
  const auto data = swum::synthesize_amplitudes(truth, v, f, so);
  const fs::path path = scratch(name);
  write(path, swum::host::format_amplitude_csv(data));
  return path;
}

TEST(SwumStator, CsvHasTheContractColumnsAndEveryBranch) {
  const fs::path out = scratch("stator.csv");
  fs::remove(out);
  const CliRun r = swum_run({"stator", "--config", kLiteral, "--amplitude-v", "200", "--frequency-hz",
                             "39000:39500:250", "--out", out.string()});
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string csv = slurp(out);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "amplitude_v,frequency_hz,branch,stable,tip_normal_um,tip_tangential_um");
  // The literal motor at the paper's 400 Vpp (a 200 V amplitude, model_spec §0):
  // 39.0 kHz: three tangential branches (upper and lower stable, middle unstable); 39.25 and
  // 39.5 kHz: one each.
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 3 + 1 + 1) << csv;
  EXPECT_NE(csv.find("200,39000,1,0,"), std::string::npos) << csv;
}

TEST(SwumStator, JsonHasRowsAndTheSofteningBackbone) {
  const CliRun r = swum_run(
      {"stator", "--config", kLiteral, "--amplitude-v", "25,200", "--frequency-hz", "39500", "--json"});
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j.at("rows").size(), 2u);
  for (const char* key : {"amplitude_v", "frequency_hz", "branch", "stable", "tip_normal_um", "tip_tangential_um"}) {
    EXPECT_TRUE(j.at("rows")[0].contains(key)) << key;
  }
  ASSERT_EQ(j.at("backbone").size(), 2u);
  EXPECT_GT(j["backbone"][0]["tangential_peak_hz"].get<double>(),
            j["backbone"][1]["tangential_peak_hz"].get<double>() + 500.0);
}

TEST(SwumStator, PlotWritesBothAxes) {
  const fs::path png = scratch("stator.png");
  fs::remove(png);
  fs::remove(scratch("stator_normal.png"));
  const CliRun r = swum_run({"stator", "--config", kLiteral, "--amplitude-v", "50,200", "--frequency-hz",
                             "38500:40000:50", "--plot", png.string(), "--out", scratch("s.csv").string()});
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_GT(fs::file_size(png), 1000u);
  EXPECT_GT(fs::file_size(scratch("stator_normal.png")), 1000u);
}

TEST(SwumIdentify, RoundTripWritesANewConfigAndFlagsWhatIsNotIdentifiable) {
  const fs::path data = synthetic_csv("table2.csv", swum::MotorParameters{});
  const fs::path out = scratch("fitted.toml");
  const fs::path report = scratch("report");
  fs::remove(out);
  fs::remove_all(report);
  const std::string config_before = slurp(kLiteral);
  const CliRun r = swum_run({"identify", "--config", kLiteral, "--amplitudes", data.string(), "--out", out.string(),
                             "--report", report.string(), "--json"});
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(slurp(kLiteral), config_before);
  const auto j = nlohmann::json::parse(r.output);
  const double truth = swum::StatorParameters{}.c1111_pa;
  for (const auto& p : j.at("parameters")) {
    if (p["key"] == "c1111_pa") {
      ASSERT_TRUE(p["identifiable"].get<bool>());
      const double v = p["value"].get<double>();
      const double se = p["standard_error"].get<double>();
      EXPECT_LT(std::abs(v - truth), 2 * se);
      EXPECT_LT(std::abs(v - truth), 0.15 * std::abs(truth));
    }
    if (p["key"] == "c111_pa" || p["key"] == "e311_c_per_v_m") {
      EXPECT_FALSE(p["identifiable"].get<bool>());
      EXPECT_TRUE(p["standard_error"].is_null());  // no made-up error bar
    }
  }
  EXPECT_LT(j.at("rms_relative_residual").get<double>(), 0.03);
  // The written file parses and carries the fitted c1111; the rest of the prior is kept.
  const swum::MotorParameters fitted = swum::parse_motor_parameters(slurp(out), out.string());
  EXPECT_NEAR(fitted.stator.c1111_pa, truth, 0.15 * std::abs(truth));
  EXPECT_DOUBLE_EQ(fitted.stator.tip_lever_over_length, 0.1321);
  EXPECT_GT(fs::file_size(report / "fit_tangential.png"), 1000u);
  EXPECT_GT(fs::file_size(report / "fit_normal.png"), 1000u);
  EXPECT_TRUE(fs::exists(report / "residuals.csv"));
}

TEST(SwumIdentify, TablePrintsStandardErrorsAndTheResidual) {
  const fs::path data = synthetic_csv("linear.csv", swum::linearised(swum::MotorParameters{}));
  const CliRun r = swum_run({"identify", "--config", kLiteral, "--amplitudes", data.string(), "--out",
                             scratch("fitted_linear.toml").string()});
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("c1111_pa"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("NOT significantly non-zero"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find(", significantly non-zero"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("not identifiable, kept at prior"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("RMS residual"), std::string::npos) << r.output;
}

struct BadCsv {
  const char* name;
  const char* text;
  const char* expected;  // in the one-line message
};
// Printed by name, so the ctest names are the same on every build (not the object's bytes).
void PrintTo(const BadCsv& b, std::ostream* os) { *os << b.name; }

class SwumIdentifyRejects : public ::testing::TestWithParam<BadCsv> {};

TEST_P(SwumIdentifyRejects, MalformedCsvWithFileLineColumn) {
  const fs::path data = scratch(std::string(GetParam().name) + ".csv");
  write(data, GetParam().text);
  const fs::path out = scratch(std::string(GetParam().name) + ".toml");
  fs::remove(out);
  const CliRun r = swum_run({"identify", "--config", kLiteral, "--amplitudes", data.string(), "--out", out.string()});
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find(data.string() + ":" + GetParam().expected), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, SwumIdentifyRejects,
    ::testing::Values(
        BadCsv{"missing_column", "amplitude_v,frequency_hz,tip_normal_um\n50,39500,0.4\n",
               "1:4: missing column tip_tangential_um"},
        BadCsv{"non_numeric",
               "amplitude_v,frequency_hz,tip_normal_um,tip_tangential_um\n50,39500,0.4,0.7\n100,39500,x,1\n",
               "3:3: column tip_normal_um: 'x' is not a number"},
        BadCsv{"negative_voltage", "amplitude_v,frequency_hz,tip_normal_um,tip_tangential_um\n-50,39500,0.4,0.7\n",
               "2:1: column amplitude_v: negative value"},
        BadCsv{"too_few",
               "amplitude_v,frequency_hz,tip_normal_um,tip_tangential_um\n50,39500,0.4,0.7\n100,39500,0.8,\n",
               "3: only 3 amplitude values"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(SwumIdentify, RefusesToOverwriteTheInputConfig) {
  const fs::path data = synthetic_csv("t.csv", swum::MotorParameters{});
  const fs::path copy = scratch("copy.toml");
  write(copy, slurp(kLiteral));
  const CliRun r = swum_run(
      {"identify", "--config", copy.string(), "--amplitudes", data.string(), "--out", copy.string()});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(slurp(copy), slurp(kLiteral));
}

}  // namespace
