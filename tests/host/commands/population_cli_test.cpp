// `swum population` on the real binary: zero spread reproduces `swum pick --config`; the spread
// of the operating frequency follows the spread of the stator's stiffness; rejected draws are
// recorded; every bad argument or spreads file is a one-line error with its exit status.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "swum_cli_runner.h"
#include "test_paths.h"

namespace {

using swum::test::run_swum;
const std::string kConfig = swum::test::source_path("config/li2019.toml");
const std::string kGrid = "39300:40600:50";

std::string write_scratch(const std::string& name, const std::string& text) {
  const auto path = swum::test::scratch_path("population", name);
  std::ofstream(path) << text;
  return path.string();
}

std::vector<std::vector<std::string>> csv_rows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::istringstream cells_in(line);
    std::string cell;
    while (std::getline(cells_in, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    rows.push_back(cells);
  }
  return rows;
}

// One operating point (issue 34): with every default (grid, margin) a motor without spread is picked
// as `swum pick --config` and `swum band` pick it, to the bit.
TEST(SwumPopulation, WithTheDefaultsPicksAsSwumPickAndBand) {
  const std::string spreads = write_scratch("zero_defaults.toml",
                                            "[contact]\npreload_n = { distribution = \"normal\", sigma = 0 }\n");
  const auto out = swum::test::scratch_path("population", "zero_defaults.csv");
  const auto summary = swum::test::scratch_path("population", "zero_defaults.json");
  auto r = run_swum({"population", "--config", kConfig, "--spreads", spreads, "--motors", "1", "--amplitude-v", "350",
                     "--out", out.string(), "--summary", summary.string()});
  ASSERT_EQ(r.status, 0) << r.output;
  const auto s = nlohmann::json::parse(swum::test::read_file(summary));
  const auto& v = s.at("voltages").at(0);
  ASSERT_EQ(v.at("decided").get<int>(), 1) << s.dump();
  r = run_swum({"pick", "--config", kConfig, "--amplitude-v", "350", "--json"});
  ASSERT_EQ(r.status, 0) << r.output;
  const double pick = nlohmann::json::parse(r.output).at(0).at("frequency_hz").get<double>();
  r = run_swum({"band", "--config", kConfig, "--amplitude-v", "350", "--json"});
  ASSERT_EQ(r.status, 0) << r.output;
  const double band = nlohmann::json::parse(r.output).at("rows").at(0).at("frequency_hz").get<double>();
  EXPECT_EQ(v.at("frequency_hz").at("min").get<double>(), pick) << s.dump();
  EXPECT_EQ(pick, band);
}

TEST(SwumPopulation, ZeroSpreadReproducesSwumPickConfigExactly) {
  const std::string spreads = write_scratch("zero.toml",
                                            "[contact]\npreload_n = { distribution = \"normal\", sigma = 0 }\n");
  const auto out = swum::test::scratch_path("population", "zero.csv");
  const auto summary = swum::test::scratch_path("population", "zero.json");
  auto r = run_swum({"population", "--config", kConfig, "--spreads", spreads, "--motors", "2", "--amplitude-v", "300",
                     "--frequency-hz", kGrid, "--out", out.string(), "--summary", summary.string()});
  ASSERT_EQ(r.status, 0) << r.output;
  r = run_swum({"pick", "--config", kConfig, "--amplitude-v", "300", "--frequency-hz", kGrid, "--json"});
  ASSERT_EQ(r.status, 0) << r.output;
  const auto pick = nlohmann::json::parse(r.output).at(0);
  const auto s = nlohmann::json::parse(swum::test::read_file(summary));
  const auto& v = s.at("voltages").at(0);
  ASSERT_EQ(v.at("decided").get<int>(), 2) << s.dump();
  for (const char* q : {"min", "max"}) {
    EXPECT_EQ(v.at("frequency_hz").at(q).get<double>(), pick.at("frequency_hz").get<double>()) << s.dump();
    EXPECT_EQ(v.at("speed_mm_s").at(q).get<double>(), pick.at("speed_mm_s").get<double>()) << s.dump();
  }
  const auto& range = s.at("oscillator_range");
  EXPECT_TRUE(range.at("reached").get<bool>());
  EXPECT_EQ(range.at("width_hz").get<double>(), 0.0);
  const auto rows = csv_rows(swum::test::read_file(out));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0][0], "motor");
  EXPECT_EQ(rows[0][2], "contact.preload_n");
  EXPECT_EQ(rows[1][1], "ok");
  EXPECT_EQ(rows[1][2], "24.8");
}

// The free stator's L1 frequency (its stiffness over its mass) scattered by 0 or by 150 Hz:
// the operating frequencies scatter with it and follow it motor by motor.
TEST(SwumPopulation, OperatingFrequencySpreadGrowsWithTheStiffnessSpread) {
  auto study = [](const std::string& name, const std::string& sigma) {
    const std::string spreads = write_scratch(
        name + ".toml", "[stator]\ntarget_l1_frequency_hz = { distribution = \"normal\", sigma = " + sigma + " }\n");
    const auto out = swum::test::scratch_path("population", name + ".csv");
    const auto r = run_swum({"population", "--config", kConfig, "--spreads", spreads, "--motors", "5", "--amplitude-v",
                             "300", "--frequency-hz", "39000:41000:50", "--seed", "3", "--yield", "0.6", "--json",
                             "--out", out.string()});
    EXPECT_EQ(r.status, 0) << r.output;
    return std::pair{nlohmann::json::parse(r.output.substr(r.output.find('{'))), csv_rows(swum::test::read_file(out))};
  };
  const auto [narrow, narrow_rows] = study("narrow", "0");
  const auto [wide, wide_rows] = study("wide", "150");
  const auto width = [](const nlohmann::json& s) {
    const auto& f = s.at("voltages").at(0).at("frequency_hz");
    return f.at("max").get<double>() - f.at("min").get<double>();
  };
  EXPECT_EQ(width(narrow), 0.0) << narrow.dump();
  EXPECT_GE(width(wide), 150.0) << wide.dump();
  // Motor by motor: a stiffer stator runs higher (pairs of decided motors in the same order).
  std::vector<std::pair<double, double>> l1_and_f;
  for (std::size_t i = 1; i < wide_rows.size(); ++i) {
    if (wide_rows[i][1] == "ok") l1_and_f.emplace_back(std::stod(wide_rows[i][2]), std::stod(wide_rows[i][3]));
  }
  ASSERT_GE(l1_and_f.size(), 4u);
  std::sort(l1_and_f.begin(), l1_and_f.end());
  for (std::size_t i = 1; i < l1_and_f.size(); ++i) {
    EXPECT_GE(l1_and_f[i].second, l1_and_f[i - 1].second)
        << "L1 " << l1_and_f[i].first << " Hz runs lower than L1 " << l1_and_f[i - 1].first << " Hz";
  }
}

// A drawn set that breaks a rule between parameters (explicit geometry: half height below the
// length) is recorded as rejected, with why, and counts against the yield.
TEST(SwumPopulation, RejectedDrawsAreRecordedAndCountAgainstTheYield) {
  std::string config = swum::test::read_file(kConfig);
  const std::string from = "geometry = \"from_frequencies\"";
  config.replace(config.find(from), from.size(), "geometry = \"explicit\"");
  const std::string explicit_config = write_scratch("explicit.toml", config);
  const std::string spreads = write_scratch(
      "rejects.toml", "[stator]\nhalf_height_mm = { distribution = \"uniform\", min = 5.3, max = 5.8 }\n"
                      "length_mm = { distribution = \"uniform\", min = 5.0, max = 5.6 }\n");
  const auto out = swum::test::scratch_path("population", "rejects.csv");
  const auto r = run_swum({"population", "--config", explicit_config, "--spreads", spreads, "--motors", "6",
                           "--amplitude-v", "300", "--frequency-hz", "40000", "--out", out.string()});
  EXPECT_EQ(r.status, 1) << r.output;  // one frequency: nothing can be picked, no yield
  EXPECT_NE(r.output.find("no oscillator range reaches 95 % yield"), std::string::npos) << r.output;
  int rejected = 0;
  for (const auto& row : csv_rows(swum::test::read_file(out))) {
    if (row[1] != "rejected") continue;
    ++rejected;
    // Columns in parameter-table order: length_mm, then half_height_mm.
    EXPECT_GE(std::stod(row[3]), std::stod(row[2])) << "half height below the length, yet rejected";
    EXPECT_NE(row.back().find("half_height_mm must be smaller than stator.length_mm"), std::string::npos);
  }
  EXPECT_GE(rejected, 1) << swum::test::read_file(out);
  EXPECT_NE(r.output.find(std::to_string(rejected) + " rejected draws"), std::string::npos) << r.output;
}

TEST(SwumPopulation, BadInputIsAOneLineErrorNamingWhatAndWhere) {
  const std::string good = swum::test::source_path("config/population.toml");
  const std::string bad = write_scratch(
      "bad.toml", "[contact]\n# a comment\npreload_n = { distribution = \"normal\", sigma = -2 }\n");
  const std::string out = swum::test::scratch_path("population", "never.csv").string();
  struct Case {
    std::vector<std::string> args;
    int status;
    std::string words;
  };
  const std::vector<Case> cases = {
      {{"--motors", "0"}, 2, "--motors: must be within 1..1000000"},
      {{"--motors", "-3"}, 2, "--motors"},
      {{"--yield", "1.5"}, 2, "--yield"},
      {{"--amplitude-v", "100,abc"}, 2, "--amplitude-v"},
      {{"--amplitude-v", "100,100"}, 2, "--amplitude-v: a voltage is given twice"},
      {{"--amplitude-v", "100,100.00005"}, 2, "--amplitude-v: a voltage is given twice"},  // one curve to the pick
      {{"--seed", "-1"}, 2, "--seed"},
      {{"--frequency-hz", "41000:39000:50"}, 2, "--frequency-hz"},
      {{"--margin-hz", "-1"}, 2, "--margin-hz"},
      {{"--jobs", "5000"}, 2, "--jobs"},
      {{"--spreads", bad}, 1, bad + ":3: contact.preload_n: sigma -2 is negative"},
      {{"--spreads", "/nonexistent/spreads.toml"}, 1, "/nonexistent/spreads.toml"},
      {{"--config", "/nonexistent/motor.toml"}, 1, "/nonexistent/motor.toml"},
      {{"--out", "/nonexistent/dir/motors.csv"}, 1, "/nonexistent/dir/motors.csv.partial"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = {"population", "--config",      kConfig, "--spreads", good, "--motors",
                                     "3",          "--amplitude-v", "300",   "--out",     out};
    for (std::size_t k = 0; k + 1 < c.args.size(); k += 2) {
      const auto it = std::find(args.begin(), args.end(), c.args[k]);
      if (it != args.end()) {
        *(it + 1) = c.args[k + 1];
      } else {
        args.push_back(c.args[k]);
        args.push_back(c.args[k + 1]);
      }
    }
    const auto r = run_swum(args);
    EXPECT_EQ(r.status, c.status) << c.words << ": " << r.output;
    EXPECT_EQ(r.output.rfind("swum: error: ", 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find(c.words), std::string::npos) << c.words << ": " << r.output;
  }
  EXPECT_FALSE(std::ifstream(out).good()) << "a refused study wrote its file";
}

}  // namespace
