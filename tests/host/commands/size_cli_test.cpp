// `swum size` on the real binary: the oscillator range is `swum band`'s on the same grid, the
// figures hang together physically, the clamped capacitance shows up at the terminals as w C0 V
// (the board designer's check of host.live.board_current_modbus, here on the sizing's own
// figures), the report folder, and the one-line errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "swum_cli_runner.h"
#include "test_paths.h"

namespace {

using swum::test::run_swum;
const std::string kConfig = swum::test::source_path("config/li2019.toml");
const std::vector<std::string> kGrid = {"--amplitude-v", "100,400", "--frequency-hz", "39000:40500:50"};

std::vector<std::string> with(std::vector<std::string> head, const std::vector<std::string>& tail) {
  head.insert(head.end(), tail.begin(), tail.end());
  return head;
}

TEST(SwumSize, OscillatorRangeIsSwumBandsAndTheFiguresHangTogether) {
  const auto report = swum::test::scratch_path("size", "report");
  std::filesystem::remove_all(report);
  auto r = run_swum(with({"size", "--config", kConfig, "--json", "--report", report.string()}, kGrid));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  auto b = run_swum(with({"band", "--config", kConfig, "--json"}, kGrid));
  ASSERT_EQ(b.status, 0) << b.output;
  const auto band = nlohmann::json::parse(b.output);
  EXPECT_EQ(j.at("oscillator").at("low_hz"), band.at("band").at("low_hz"));
  EXPECT_EQ(j.at("oscillator").at("high_hz"), band.at("band").at("high_hz"));
  ASSERT_EQ(j.at("rows_sized"), 2);
  for (const auto& row : j.at("table")) {
    const double v = row.at("amplitude_v");
    for (const char* phase : {"phase_a", "phase_b"}) {
      const auto& p = row.at(phase);
      const double rms = p.at("current_rms_a"), amplitude = p.at("current_amplitude_a"), peak = p.at("current_peak_a");
      // A sinusoidal drive: the current is nearly its fundamental (RMS = amplitude / sqrt 2 within
      // the harmonics of the non-linear motion), its largest sample at least the amplitude's.
      EXPECT_NEAR(rms, amplitude / std::numbers::sqrt2, 0.03 * rms) << v << " V " << phase;
      EXPECT_GE(peak, 0.97 * amplitude) << v << " V " << phase;
      EXPECT_NEAR(p.at("voltage_v").get<double>(), v, 1e-6 * v);
      EXPECT_GT(p.at("power_w").get<double>(), 0.0);
      EXPECT_LE(p.at("power_w").get<double>(), p.at("apparent_power_va").get<double>());
      EXPECT_NEAR(p.at("power_factor").get<double>(),
                  p.at("power_w").get<double>() / p.at("apparent_power_va").get<double>(), 1e-9);
      // Above the peak the motor is capacitive: C0 dominates the susceptance.
      EXPECT_GT(p.at("susceptance_siemens").get<double>(), 0.0);
    }
    // Unloaded rows do no mechanical work; the heat into the stator is part of what the phases take in.
    EXPECT_EQ(row.at("mechanical_power_w").get<double>(), 0.0);
    EXPECT_LT(row.at("stator_heat_w").get<double>(), row.at("electrical_power_w").get<double>());
  }
  const auto& net = j.at("network");
  EXPECT_EQ(net.at("amplitude_v"), 400.0);  // the design row: the highest voltage
  const double f = j.at("table")[1].at("frequency_hz");
  const double w = 2.0 * std::numbers::pi * f;
  EXPECT_NEAR(net.at("phase_a").at("c0_parallel_inductance_uh").get<double>(), 1e6 / (w * w * 10e-9), 1e-6);
  // The parallel inductor cancels the whole susceptance, so it is below the C0-only one.
  EXPECT_LT(net.at("phase_a").at("parallel_inductance_uh").get<double>(),
            net.at("phase_a").at("c0_parallel_inductance_uh").get<double>());
  EXPECT_NEAR(j.at("table")[1].at("phase_a").at("parallel_amplifier_phase_deg").get<double>(), 0.0, 1e-6);
  // The series design repeated in the simulator holds phase A within 2 % of the design voltage.
  const auto& series = j.at("series_in_loop");
  ASSERT_TRUE(series.at("converged").get<bool>()) << series;
  EXPECT_NEAR(series.at("terminal_a_v").get<double>(), 400.0, 0.02 * 400.0);
  EXPECT_LT(series.at("source_voltage_v").get<double>(), 100.0);  // a step-up
  const std::string md = swum::test::read_file(report / "report.md");
  EXPECT_NE(md.find("## What to buy"), std::string::npos) << md;
  EXPECT_NE(md.find("parallel inductor of"), std::string::npos) << md;
  // With the series design found in the loop, the one-shot series figures point to it, not to a
  // sizing still to be done.
  EXPECT_NE(md.find("to the figures sized in the loop below"), std::string::npos) << md;
  EXPECT_EQ(md.find("must be sized again"), std::string::npos) << md;
  for (const char* png : {"admittance_magnitude.png", "current_vs_frequency.png", "envelope_current.png"}) {
    EXPECT_TRUE(std::filesystem::exists(report / png)) << png;
    EXPECT_NE(md.find(png), std::string::npos) << png;
  }
  EXPECT_EQ(nlohmann::json::parse(swum::test::read_file(report / "summary.json")), j);
}

// With an ideal source C0 does not touch the mechanics: the same picks, and every row's
// susceptance grows by exactly w dC0 (a voltage read as twice or half the terminal amplitude
// would make it 2 or 0.5 w dC0 V in current).
TEST(SwumSize, MoreClampedCapacitanceAddsOmegaTimesItToTheSusceptanceAndNothingElse) {
  const auto config = swum::test::scratch_path("size", "c0.toml");
  {
    std::string text = swum::test::read_file(kConfig);
    const std::string section = "[stator]\n";
    const auto at = text.find(section);
    ASSERT_NE(at, std::string::npos);
    text.insert(at + section.size(), "clamped_capacitance_nf = 12.5\n");
    std::ofstream(config) << text;
  }
  const std::vector<std::string> grid = {"--amplitude-v", "200", "--frequency-hz", "39400:40500:50", "--json"};
  auto base = run_swum(with({"size", "--config", kConfig}, grid));
  auto more = run_swum(with({"size", "--config", config.string()}, grid));
  ASSERT_EQ(base.status, 0) << base.output;
  ASSERT_EQ(more.status, 0) << more.output;
  const auto j0 = nlohmann::json::parse(base.output), j1 = nlohmann::json::parse(more.output);
  const auto& r0 = j0.at("table")[0];
  const auto& r1 = j1.at("table")[0];
  ASSERT_EQ(r0.at("frequency_hz"), r1.at("frequency_hz"));
  const double w = 2.0 * std::numbers::pi * r0.at("frequency_hz").get<double>();
  for (const char* phase : {"phase_a", "phase_b"}) {
    const double db = r1.at(phase).at("susceptance_siemens").get<double>() -
                      r0.at(phase).at("susceptance_siemens").get<double>();
    EXPECT_NEAR(db, w * 2.5e-9, 0.01 * w * 2.5e-9) << phase;
    EXPECT_NEAR(r1.at(phase).at("conductance_siemens").get<double>(),
                r0.at(phase).at("conductance_siemens").get<double>(),
                1e-3 * r0.at(phase).at("conductance_siemens").get<double>())
        << phase;
  }
}

// A population: the motors drawn as `swum population` draws them, each sized with the nominal
// network; a larger share of the motors needs at least as much of everything.
TEST(SwumSize, APopulationNeedsMoreForALargerShareOfItsMotors) {
  const std::string spreads = swum::test::source_path("config/population.toml");
  auto run = [&](const char* yield) {
    auto r = run_swum({"size", "--config", kConfig, "--amplitude-v", "400", "--frequency-hz", "39000:40500:50",
                       "--spreads", spreads, "--motors", "4", "--seed", "3", "--yield", yield, "--json"});
    EXPECT_EQ(r.status, 0) << r.output;
    return nlohmann::json::parse(r.output);
  };
  const auto all = run("1"), quarter = run("0.25");
  const auto& p = all.at("population");
  EXPECT_EQ(p.at("motors"), 4);
  EXPECT_EQ(p.at("needed"), 4);
  EXPECT_EQ(quarter.at("population").at("needed"), 1);
  ASSERT_EQ(p.at("sized"), 4);
  for (const char* figure : {"current_rms_a", "current_peak_a", "apparent_power_va", "parallel_amplifier_current_a",
                             "series_source_voltage_v"}) {
    EXPECT_LE(quarter.at("population").at(figure).get<double>(), p.at(figure).get<double>()) << figure;
  }
  EXPECT_LE(quarter.at("population").at("oscillator").at("width_hz").get<double>(),
            p.at("oscillator").at("width_hz").get<double>());
  // The nominal motor's network and figures do not depend on the population.
  EXPECT_EQ(all.at("network"), quarter.at("network"));
  EXPECT_EQ(all.at("table"), quarter.at("table"));
}

// A config with an output network is refused (swum size sizes one for an ideal source), and a
// row that cannot be sized keeps the CSV's columns.
TEST(SwumSize, RefusesAnOutputNetworkAndKeepsTheColumnsOfAnUnsizedRow) {
  const auto config = swum::test::scratch_path("size", "network.toml");
  std::ofstream(config) << swum::test::read_file(kConfig) << "\n[amplifier]\nparallel_inductance_uh = 1600\n";
  auto r = run_swum({"size", "--config", config.string(), "--amplitude-v", "200"});
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("[amplifier] sets an output network"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  const auto out = swum::test::scratch_path("size", "unsized.csv");
  auto u = run_swum({"size", "--config", kConfig, "--amplitude-v", "100,400", "--frequency-hz", "39000:40000:50",
                     "--out", out.string()});
  EXPECT_EQ(u.status, 1) << u.output;  // 100 V is undecided on this grid
  const std::string csv = swum::test::read_file(out);
  std::size_t lines = 0;
  for (std::size_t at = 0; at < csv.size();) {
    const std::size_t end = csv.find('\n', at);
    const std::string line = csv.substr(at, end - at);
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 30) << line;
    at = end + 1;
    ++lines;
  }
  EXPECT_EQ(lines, 3u);
  EXPECT_NE(csv.find("\n100,0,0,0,"), std::string::npos) << csv;
}

struct BadSize {
  std::vector<std::string> args;
  std::string message;  // what the one line must contain
};

class SwumSizeRejects : public ::testing::TestWithParam<BadSize> {};

TEST_P(SwumSizeRejects, WithOneLineNamingTheProblem) {
  std::vector<std::string> args = {"size", "--config", kConfig};
  args.insert(args.end(), GetParam().args.begin(), GetParam().args.end());
  auto r = run_swum(args);
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find(GetParam().message), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

INSTANTIATE_TEST_SUITE_P(
    BadInput, SwumSizeRejects,
    ::testing::Values(BadSize{{"--amplitude-v", "-100"}, "--amplitude-v"},
                      BadSize{{"--amplitude-v", "200", "--load", "5000"}, "--load"},
                      BadSize{{"--amplitude-v", "200", "--temperature-rise-k", "30"}, "--temperature-rise-k"},
                      BadSize{{"--amplitude-v", "200", "--frequency-hz", "40000:40050:50"}, "--frequency-hz"},
                      BadSize{{"--amplitude-v", "200", "--margin-hz", "-5"}, "--margin-hz"},
                      BadSize{{"--amplitude-v", "200", "--report", "/proc/version/x"}, "report directory"},
                      BadSize{{"--amplitude-v", "200", "--out", "/nonexistent/dir/rows.csv"}, "is not a directory"},
                      BadSize{{"--amplitude-v", "200", "--yield", "0"}, "--yield"},
                      BadSize{{"--amplitude-v", "200", "--source-resistance-ohm", "0"}, "--source-resistance-ohm"},
                      BadSize{{"--amplitude-v", "200", "--motors", "10"}, "needs --spreads"},
                      BadSize{{"--amplitude-v", "200", "--yield", "1.5"}, "--yield"},
                      BadSize{{"--amplitude-v", "200", "--motors", "0", "--spreads", "x.toml"}, "--motors"},
                      BadSize{{"--amplitude-v", "200", "--spreads", "/nonexistent/spreads.toml"}, "spreads.toml"}));

}  // namespace
