// `swum track` and `swum track-report` on the real binary: the one-line errors with their exit
// statuses (bad --method, --motional-phase-deg without the phase method, no device, a device that does not
// answer; --run without '=', missing files, a band that does not cover the run), and
// track-report's text and JSON on small hand-written files. The runs on a live device are in
// track_thermal.py.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "swum_cli_runner.h"

namespace {

using swum::test::run_swum;

// A port nothing listens on: the connection is refused at once.
const std::string kNoDevice = "tcp://127.0.0.1:1";
const std::string kRefused =
    "swum: error: modbus tcp://127.0.0.1:1: cannot connect: Connection refused (is swum-emu or the board listening "
    "there?)\n";

std::string scratch(const std::string& name) { return swum::test::scratch_path("track_cli", name).string(); }

struct BadTrack {
  std::vector<std::string> args;
  int status;
  std::string message;  // the whole output: one line
};

void PrintTo(const BadTrack& b, std::ostream* os) {
  for (const std::string& arg : b.args) *os << arg << ' ';
  *os << "-> " << b.status;
}

class SwumTrackRejects : public ::testing::TestWithParam<BadTrack> {};

TEST_P(SwumTrackRejects, WithOneLineAndWritesNothing) {
  const std::string out = scratch("refused.csv");
  std::filesystem::remove(out);
  std::filesystem::remove(out + ".partial");
  std::vector<std::string> args = {"track", "--out", out};
  args.insert(args.end(), GetParam().args.begin(), GetParam().args.end());
  const auto r = run_swum(args);
  EXPECT_EQ(r.status, GetParam().status) << r.output;
  EXPECT_EQ(r.output, GetParam().message);
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(out + ".partial"));
}

INSTANTIATE_TEST_SUITE_P(
    BadInput, SwumTrackRejects,
    ::testing::Values(
        BadTrack{{"--modbus", kNoDevice, "--amplitude-v", "400", "--method", "x"},
                 2,
                 "swum: error: --method: x: expected phase, speed or fixed\n"},
        BadTrack{{"--modbus", kNoDevice, "--amplitude-v", "400", "--method", "speed", "--motional-phase-deg", "-10"},
                 2,
                 "swum: error: --motional-phase-deg: only with --method phase\n"},
        BadTrack{{"--modbus", kNoDevice, "--amplitude-v", "400", "--method", "fixed", "--motional-phase-deg", "-10"},
                 2,
                 "swum: error: --motional-phase-deg: only with --method phase\n"},
        BadTrack{{"--amplitude-v", "400"},
                 2,
                 "swum: error: no device: give --modbus tcp://HOST:PORT | rtu:DEVICE:BAUD, --can "
                 "IFACE[:NODE] or --canopen IFACE:NODE\n"},
        BadTrack{{"--modbus", kNoDevice}, 2, "swum: error: --amplitude-v is required (see swum --help)\n"},
        BadTrack{{"--modbus", kNoDevice, "--amplitude-v", "400", "--bogus"},
                 2,
                 "swum: error: The following argument was not expected: --bogus (see swum --help)\n"},
        // A device that does not answer: exit 1, nothing written.
        BadTrack{{"--modbus", kNoDevice, "--amplitude-v", "400"}, 1, kRefused},
        BadTrack{{"--modbus", kNoDevice, "--amplitude-v", "400", "--method", "speed"}, 1, kRefused}));

TEST(SwumTrack, OutIsRequired) {
  const auto r = run_swum({"track", "--modbus", kNoDevice, "--amplitude-v", "400"});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output, "swum: error: --out is required (see swum --help)\n");
}

TEST(SwumTrack, NumericSettingsAreCheckedBeforeTheDeviceIsOpened) {
  // Against a device that does not answer the option's error comes first, and nothing is written.
  const std::string out = scratch("numeric.csv");
  const std::pair<std::vector<std::string>, std::string> cases[] = {
      {{"--amplitude-v", "0"}, "--amplitude-v: must be in (0, 10000]"},
      {{"--amplitude-v", "400", "--margin-hz", "-5"}, "--margin-hz: -5 outside 0..5000"},
      {{"--amplitude-v", "400", "--cycle-ms", "0"}, "--cycle-ms: must be within (0, 10000]"},
  };
  for (const auto& [extra, message] : cases) {
    std::filesystem::remove(out + ".partial");
    std::vector<std::string> args = {"track", "--modbus", kNoDevice, "--out", out};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_swum(args);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_EQ(r.output, "swum: error: " + message + "\n");
    EXPECT_FALSE(std::filesystem::exists(out + ".partial")) << message;
  }
}

const std::string kBandHeader =
    "amplitude_v,load_n,temperature_rise_k,decided,frequency_hz,speed_mm_s,peak_frequency_hz,peak_speed_mm_s,margin_hz,"
    "collapse_hz,reason\n";
const std::string kTrackHeader =
    "cycle,time_s,mode,frequency_hz,speed_mm_s,motional_phase_a_deg,phase_a_deg,current_a_a,current_b_a,power_w,"
    "stator_temperature_c,state,fault_code\n";

// Written whole, then renamed in place: tests running in parallel read one file or the other,
// never half of one.
std::string write(const std::string& name, const std::string& text) {
  const std::string path = scratch(name);
  const std::string part = path + "." + std::to_string(::getpid());
  std::ofstream(part) << text;
  std::filesystem::rename(part, path);
  return path;
}

// Best 600 mm/s at a 0 K rise, 500 at 20 K; the run at 90 % of it while warming from 20 to 40 degC.
std::string band() {
  return write("band.csv", kBandHeader + "400,0,0,1,39600,600,39500,610,100,39450,ok\n"
                                         "400,0,20,1,39400,500,39300,510,100,39250,ok\n"
                                         "400,0,40,0,,,,,,,speed is highest at the bottom of the sweep\n");
}
std::string run_file() {
  return write("run.csv", kTrackHeader + "0,1.000000,hold,39600.000,540.000,,,,,,20.000,1,0\n"
                                         "1,2.000000,hold,39500.000,495.000,,,,,,30.000,1,0\n"
                                         "2,3.000000,hold,39400.000,450.000,,,,,,40.000,1,0\n");
}

TEST(SwumTrackReport, SharesAsTextAndJson) {
  const std::string run = "phase=" + run_file();
  auto r = run_swum(
      {"track-report", "--run", run, "--band", band(), "--amplitude-v", "400", "--skip-s", "0", "--block-s", "10"});
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output, "run      min share  final share  final frequency (Hz)  final margin (Hz)  final rise (K)\n"
                      "phase        0.900        0.900               39400.0              100.0            20.0\n");
  r = run_swum({"track-report", "--run", run, "--band", band(), "--amplitude-v", "400", "--skip-s", "0", "--block-s",
                "2", "--json"});
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0].at("run"), "phase");
  EXPECT_DOUBLE_EQ(j[0].at("min_share").get<double>(), 0.9);
  EXPECT_EQ(j[0].at("final_rise_k"), 20.0);
  EXPECT_EQ(j[0].at("final_margin_hz"), 100.0);
  const auto& blocks = j[0].at("blocks");
  ASSERT_EQ(blocks.size(), 2u);
  EXPECT_EQ(blocks[0].at("start_s"), 1.0);
  EXPECT_EQ(blocks[0].at("end_s"), 2.0);
  EXPECT_DOUBLE_EQ(blocks[0].at("best_speed_mm_s").get<double>(), 575.0);
  EXPECT_EQ(blocks[1].at("start_s"), 3.0);
}

std::string hot_run_file() {  // 30.5 K above ambient at t = 2 s: beyond the band's 20 K
  return write("hot.csv", kTrackHeader + "0,1,hold,39600,540,,,,,,20,1,0\n1,2,hold,39500,495,,,,,,50.5,1,0\n");
}

// @band, @run, @hot and @missing stand for the scratch files (written when the test runs).
std::string with_files(std::string text) {
  const std::pair<std::string, std::string> files[] = {
      {"@band", band()}, {"@run", run_file()}, {"@hot", hot_run_file()}, {"@missing", scratch("missing.csv")}};
  for (const auto& [token, path] : files) {
    for (std::size_t at = text.find(token); at != std::string::npos; at = text.find(token, at + path.size()))
      text.replace(at, token.size(), path);
  }
  return text;
}

struct BadReport {
  std::vector<std::string> args;  // after --band @band --amplitude-v 400
  int status;
  std::string message;
};

void PrintTo(const BadReport& b, std::ostream* os) {
  for (const std::string& arg : b.args) *os << arg << ' ';
  *os << "-> " << b.status;
}

class SwumTrackReportRejects : public ::testing::TestWithParam<BadReport> {};

TEST_P(SwumTrackReportRejects, WithOneLine) {
  std::filesystem::remove(scratch("missing.csv"));
  std::vector<std::string> args = {"track-report", "--band", band(), "--amplitude-v", "400"};
  for (const std::string& arg : GetParam().args) args.push_back(with_files(arg));
  const auto r = run_swum(args);
  EXPECT_EQ(r.status, GetParam().status) << r.output;
  EXPECT_EQ(r.output, with_files(GetParam().message));
}

INSTANTIATE_TEST_SUITE_P(
    BadInput, SwumTrackReportRejects,
    ::testing::Values(BadReport{{"--run", "phase"}, 2, "swum: error: --run: phase: expected NAME=FILE\n"},
                      BadReport{{"--run", "=@run"}, 2, "swum: error: --run: =@run: expected NAME=FILE\n"},
                      BadReport{{"--run", "phase="}, 2, "swum: error: --run: phase=: expected NAME=FILE\n"},
                      BadReport{{"--run", "phase=@missing"}, 1, "swum: error: @missing: cannot open\n"},
                      BadReport{{}, 2, "swum: error: --run is required (see swum --help)\n"},
                      BadReport{{"--run", "phase=@run", "--skip-s", "0", "--block-s", "0"},
                                2,
                                "swum: error: --block-s: must be in (0, 1e6]\n"},
                      BadReport{{"--run", "phase=@run"}, 1, "swum: error: phase: no rows after --skip-s\n"},
                      BadReport{{"--run", "hot=@hot", "--skip-s", "0"},
                                1,
                                "swum: error: hot: temperature rise 30.5 K at t = 2 s outside the band's 0..20 K\n"},
                      BadReport{{"--run", "phase=@run", "--load", "1"},
                                1,
                                "swum: error: @band: fewer than two decided rows at 400 V and 1 N\n"}));

TEST(SwumTrackReport, AMissingBandFileIsNamed) {
  const std::string missing = scratch("no_band.csv");
  std::filesystem::remove(missing);
  const auto r = run_swum({"track-report", "--run", "phase=" + run_file(), "--band", missing, "--amplitude-v", "400"});
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_EQ(r.output, "swum: error: " + missing + ": cannot open\n");
}

// A usage error (exit 2) is not hidden behind a file error (exit 1): every --run's NAME=FILE form
// is checked before the band or a run is read.
TEST(SwumTrackReport, RunSyntaxIsCheckedBeforeAnyFileIsRead) {
  const std::string missing = scratch("no_band.csv");
  std::filesystem::remove(missing);
  const auto r = run_swum({"track-report", "--run", "phase", "--band", missing, "--amplitude-v", "400"});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output, "swum: error: --run: phase: expected NAME=FILE\n");
}

}  // namespace
