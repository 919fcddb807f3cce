// `swum calibrate` on the real binary: one-line errors with non-zero exit statuses for bad
// input (before any fitting), and a small fit on `swum synth` data: the JSON contract, the
// identifiability verdict, fitted.toml and the report directory.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "swum_cli_runner.h"
#include "test_paths.h"

namespace {

namespace fs = std::filesystem;
using swum::test::CliRun;
using swum::test::run_swum;

const std::string kConfig = swum::test::source_path("config/li2019.toml");
const std::string kLiteralConfig = swum::test::source_path("config/li2019_literal.toml");

fs::path scratch(const std::string& name) { return swum::test::scratch_path("swum_calibrate_cli_test", name); }

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

// config/li2019.toml with the preload 24.8 -> 23.0 N (the line must be there, once).
fs::path preload_23_config() {
  std::string text = swum::test::read_file(kConfig);
  const std::string from = "\npreload_n = 24.8 ", to = "\npreload_n = 23.0 ";
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << kConfig << " has no line 'preload_n = 24.8'";
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << kConfig << ": two lines 'preload_n = 24.8'";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  const fs::path path = scratch("preload_23.toml");
  write(path, text);
  return path;
}

// A tiny measured sweep of the motor with preload 23 N: 200 and 300 V x 40.0-40.5 kHz, no
// load, speed only, 0.2 % noise (12 operating points, 4 held out).
fs::path synthesised_sweep() {
  const fs::path points = scratch("points.csv");
  std::string text = "amplitude_v,frequency_hz,load_n\n";
  for (int amplitude_v : {200, 300}) {
    for (int f = 40000; f <= 40500; f += 100) text += std::to_string(amplitude_v) + "," + std::to_string(f) + ",0\n";
  }
  write(points, text);
  const fs::path out = scratch("measured.csv");
  const CliRun s = run_swum({"synth", "--config", preload_23_config().string(), "--points", points.string(), "--noise",
                             "0.002", "--seed", "2", "--quantities", "speed", "--out", out.string()});
  EXPECT_EQ(s.status, 0) << s.output;
  return out;
}

// A refused run: a non-zero exit status that is not a crash (the shell reports a signal as
// 128 + N), exactly one line of output that names `what`, and no fitted file.
void expect_one_line_error(const std::vector<std::string>& args, const std::string& what, const fs::path& out) {
  std::vector<std::string> full{"calibrate"};
  full.insert(full.end(), args.begin(), args.end());
  full.insert(full.end(), {"--out", out.string()});
  std::string shown;
  for (const std::string& a : full) shown += " " + a;
  SCOPED_TRACE("swum" + shown);
  const CliRun r = run_swum(full);
  EXPECT_NE(r.status, -1) << "did not finish";
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_TRUE(r.status == 1 || r.status == 2) << "exit status " << r.status << ": " << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_EQ(r.output.rfind("swum: error: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find(what), std::string::npos) << "expected '" << what << "' in: " << r.output;
  EXPECT_FALSE(fs::exists(out)) << out;
}

TEST(SwumCalibrate, BadInputsAreOneLineErrorsNamingWhatAndWhere) {
  const fs::path measured = synthesised_sweep();
  const std::string m = measured.string();
  const fs::path out = scratch("never.toml");
  fs::remove(out);

  expect_one_line_error({"--config", kConfig}, "give --measured (a sweep) and/or --facts", out);
  expect_one_line_error({"--config", kConfig, "--measured", m, "--free", "contact.preload_n,contact.magic"},
                        "--free: 'contact.magic' is not a parameter calibration can fit", out);
  // A Jenkins stiffness on a rigid contact (k_t = 0) would be another contact law.
  expect_one_line_error({"--config", kLiteralConfig, "--measured", m, "--free", "contact.tangential_stiffness_n_m"},
                        "contact.tangential_stiffness_n_m cannot be fitted: the contact is rigid", out);
  expect_one_line_error({"--config", kConfig, "--measured", m, "--free", "contact.preload_n", "--candidates",
                         "contact.preload_n"},
                        "--free and --candidates", out);
  // Comma lists (docs/host.md, "Comma lists"): the same refusal as every other name list.
  expect_one_line_error({"--config", kConfig, "--measured", m, "--candidates", "contact.preload_n,,stator.c1111_pa"},
                        "--candidates: empty name in 'contact.preload_n,,stator.c1111_pa'", out);
  expect_one_line_error({"--config", kConfig, "--measured", m, "--free", "contact.preload_n,"},
                        "--free: empty name in 'contact.preload_n,'", out);
  expect_one_line_error({"--config", kConfig, "--measured", m, "--max-free", "0"}, "--max-free: must be >= 1", out);
  expect_one_line_error({"--config", kConfig, "--measured", m, "--starts", "0"}, "--starts: must be >= 1", out);
  expect_one_line_error({"--config", kConfig, "--measured", m, "--max-evaluations", "5"},
                        "--max-evaluations: must be >= 10", out);

  const fs::path missing = scratch("no_such_sweep.csv");
  fs::remove(missing);
  expect_one_line_error({"--config", kConfig, "--measured", missing.string()}, "cannot read " + missing.string(), out);

  const fs::path bad = scratch("bad.csv");
  write(bad, "amplitude_v,frequency_hz,load_n,speed_mm_s\n100,40000,0,12\n100,40100,zero,3\n");
  expect_one_line_error({"--config", kConfig, "--measured", bad.string()},
                        bad.string() + ":3:3: column load_n: 'zero' is not a number", out);

  const fs::path kind = scratch("unknown_kind.toml");
  write(kind, "[[fact]]\nkind = \"peak_frequency\"\npaper_v = 250\ntarget = 40200\ntolerance = 200\n\n"
              "[[fact]]\nkind = \"magic\"\npaper_v = 250\ntarget = 1\ntolerance = 1\n");
  expect_one_line_error({"--config", kConfig, "--facts", kind.string()}, kind.string() + ":7: unknown kind 'magic'",
                        out);
  const fs::path tolerance = scratch("tolerance_0.toml");
  write(tolerance, "[[fact]]\nkind = \"peak_frequency\"\npaper_v = 250\ntarget = 40200\ntolerance = 0\n");
  expect_one_line_error({"--config", kConfig, "--facts", tolerance.string()}, tolerance.string() + ":", out);
  expect_one_line_error({"--config", kConfig, "--facts", tolerance.string()}, "tolerance", out);

  // Six distinct operating points (one repeated): too few to hold a quarter out.
  const fs::path few = scratch("few.csv");
  write(few,
        "amplitude_v,frequency_hz,load_n,speed_mm_s\n100,40000,0,12\n200,40100,0,30\n200,40100,0,31\n100,40200,0,10\n"
        "100,40300,0,9\n100,40400,0,8\n100,40500,0,7\n");
  expect_one_line_error({"--config", kConfig, "--measured", few.string()},
                        few.string() + ": 6 distinct operating points; calibration needs at least 8", out);

  // --out into a directory that does not exist: refused before any fitting (a fit with the
  // default selection on this file would take seconds; the refusal comes back at once).
  const fs::path nowhere = scratch("no_such_dir") / "sub";
  fs::remove_all(scratch("no_such_dir"));
  expect_one_line_error({"--config", kConfig, "--measured", m}, "--out: no directory " + nowhere.string(),
                        nowhere / "fitted.toml");

  // A name given twice is refused as such, before the report directory is made.
  const fs::path report = scratch("twice_report");
  fs::remove_all(report);
  expect_one_line_error({"--config", kConfig, "--measured", m, "--free", "contact.preload_n,contact.preload_n",
                         "--report", report.string()},
                        "--free: 'contact.preload_n' is listed twice", out);
  EXPECT_FALSE(fs::exists(report));

  // --out naming an existing directory: refused before any fitting, nothing written into it.
  const fs::path directory = scratch("out_is_a_directory");
  fs::create_directories(directory);
  const CliRun r = run_swum({"calibrate", "--config", kConfig, "--measured", m, "--out", directory.string()});
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_NE(r.output.find("--out: '" + directory.string() + "' is not a file name"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_empty(directory));
}

TEST(SwumCalibrate, FitsThePreloadOfASynthesisedSweepAndHoldsE311AtItsPrior) {
  const fs::path measured = synthesised_sweep();
  const fs::path fitted = scratch("fitted.toml"), report = scratch("report");
  fs::remove(fitted);
  fs::remove_all(report);
  const CliRun r = run_swum({"calibrate", "--config", kConfig, "--measured", measured.string(), "--free",
                             "contact.preload_n,stator.e311_c_per_v_m", "--out", fitted.string(), "--report",
                             report.string(), "--json"});
  ASSERT_EQ(r.status, 0) << r.output;
  // stdout and stderr are merged: the object starts at the first '{' (a note on the input
  // file, if any, would come before it).
  const std::size_t brace = r.output.find('{');
  ASSERT_NE(brace, std::string::npos) << r.output;
  const auto j = nlohmann::json::parse(r.output.substr(brace));

  std::map<std::string, nlohmann::json> parameters;
  for (const auto& p : j["parameters"]) parameters[p["name"].get<std::string>()] = p;
  ASSERT_EQ(parameters.size(), 2u) << r.output;
  ASSERT_TRUE(parameters.count("contact.preload_n") && parameters.count("stator.e311_c_per_v_m")) << r.output;

  const auto& preload = parameters["contact.preload_n"];
  ASSERT_TRUE(preload["identifiable"].get<bool>()) << preload.dump();
  ASSERT_TRUE(preload["standard_error"].is_number()) << preload.dump();
  const double value = preload["value"], se = preload["standard_error"];
  EXPECT_NEAR(value, 23.0, 3.0 * se) << preload.dump();
  EXPECT_GT(se, 0.0);
  EXPECT_LT(se, 0.5 * preload["spread"].get<double>()) << preload.dump();
  EXPECT_EQ(preload["unit"], "N");
  EXPECT_DOUBLE_EQ(preload["prior"].get<double>(), 24.8);
  EXPECT_FALSE(preload["at_bound"].get<bool>());

  const auto& e311 = parameters["stator.e311_c_per_v_m"];
  EXPECT_FALSE(e311["identifiable"].get<bool>()) << e311.dump();
  EXPECT_TRUE(e311["standard_error"].is_null()) << e311.dump();
  EXPECT_EQ(e311["value"].get<double>(), e311["prior"].get<double>()) << e311.dump();
  EXPECT_FALSE(e311["reason"].get<std::string>().empty()) << e311.dump();

  EXPECT_TRUE(j["selection"].empty()) << "the free set was given";
  EXPECT_EQ(j["correlations"]["names"], nlohmann::json::array({"contact.preload_n"}));
  EXPECT_EQ(j["measurements"]["operating_points"], 12);
  EXPECT_GE(j["measurements"]["held_out_points"].get<int>(), 4);
  EXPECT_FALSE(j["conclusion"].get<std::string>().empty());
  EXPECT_LT(j["wall_s"].get<double>(), 30.0);

  // fitted.toml: a header naming what was fitted, then a parameter file that runs.
  ASSERT_TRUE(fs::exists(fitted));
  const std::string text = swum::test::read_file(fitted);
  EXPECT_EQ(text.rfind("# Written by `swum calibrate", 0), 0u) << text.substr(0, 200);
  EXPECT_NE(text.find("\n#   contact.preload_n = "), std::string::npos) << text.substr(0, 600);
  EXPECT_NE(text.find("\n#   stator.e311_c_per_v_m = "), std::string::npos) << text.substr(0, 600);
  const CliRun sim = run_swum(
      {"simulate", "--config", fitted.string(), "--amplitude-v", "200", "--frequency-hz", "40200", "--json"});
  EXPECT_EQ(sim.status, 0) << sim.output;

  // The report directory: report.md, summary.json (the same object) and the plots.
  EXPECT_TRUE(fs::exists(report / "report.md"));
  ASSERT_TRUE(fs::exists(report / "summary.json"));
  const auto summary = nlohmann::json::parse(swum::test::read_file(report / "summary.json"));
  EXPECT_EQ(summary["parameters"], j["parameters"]);
  int pngs = 0;
  for (const auto& entry : fs::directory_iterator(report)) pngs += entry.path().extension() == ".png";
  EXPECT_GE(pngs, 1);
}

}  // namespace
