// `swum synth` and `swum discrepancy` on the real binary: the JSON contract, the report
// directory, an augmented config that re-reads, and one-line errors with exit codes.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
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

fs::path scratch(const std::string& name) { return swum::test::scratch_path("swum_discrepancy_cli_test", name); }

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

// 32 points of a session: 120-390 V, 40.0-40.9 kHz, loads 0-3 N, 3 s apart.
fs::path points_csv() {
  const fs::path path = scratch("points.csv");
  std::string text = "amplitude_v,frequency_hz,load_n,time_s\n";
  for (int i = 0; i < 32; ++i) {
    text += std::to_string(120 + (i * 37) % 271) + "," + std::to_string(40000 + (i * 290) % 900) + "," +
            std::to_string(i % 4) + "," + std::to_string(3 * i) + "\n";
  }
  write(path, text);
  return path;
}

TEST(SwumDiscrepancy, NamesAHiddenGuideFrictionAndWritesTheReport) {
  const fs::path data = scratch("guide.csv");
  const CliRun s = run_swum({"synth", "--config", kConfig, "--effect", "guide_friction:extra_coefficient=0.04",
                             "--points", points_csv().string(), "--noise", "0.02", "--seed", "4", "--out",
                             data.string()});
  ASSERT_EQ(s.status, 0) << s.output;
  const fs::path out = scratch("report");
  fs::remove_all(out);
  const CliRun r = run_swum(
      {"discrepancy", "--config", kConfig, "--measured", data.string(), "--out", out.string(), "--json"});
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_GE(j["effects"].size(), 1u) << r.output;
  EXPECT_EQ(j["effects"][0]["name"], "guide_friction");
  const double value = j["effects"][0]["parameters"]["extra_coefficient"]["value"];
  const double se = j["effects"][0]["parameters"]["extra_coefficient"]["standard_error"];
  EXPECT_NEAR(value, 0.04, 3.0 * se);
  EXPECT_LT(j["rms_after"].get<double>(), 0.5 * j["rms_before"].get<double>());
  for (const char* file : {"report.md", "augmented.toml", "speed_mm_s.png", "tip_normal_um.png"}) {
    EXPECT_TRUE(fs::exists(out / file)) << file;
  }
  // The augmented config re-reads and runs.
  const CliRun sim = run_swum({"simulate", "--config", (out / "augmented.toml").string(), "--amplitude-v", "200",
                               "--frequency-hz", "40500", "--json"});
  EXPECT_EQ(sim.status, 0) << sim.output;
}

TEST(SwumDiscrepancy, BadInputsAreOneLineErrorsWithExitCodes) {
  const fs::path bad = scratch("bad.csv");
  write(bad, "amplitude_v,frequency_hz,load_n,speed_mm_s\n100,40000,0,12\n100,40100,zero,3\n");
  CliRun r = run_swum(
      {"discrepancy", "--config", kConfig, "--measured", bad.string(), "--out", scratch("bad_out").string()});
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find(bad.string() + ":3:3: column load_n: 'zero' is not a number"), std::string::npos) << r.output;
  r = run_swum({"discrepancy", "--config", kConfig, "--measured", bad.string(), "--out", scratch("bad_out").string(),
                "--effects", "thermal,magic"});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("unknown effect 'magic'"), std::string::npos) << r.output;
  // The discovery's options (docs/discrepancy.md, "Discovery"): refused before the file is read.
  r = run_swum({"discrepancy", "--config", kConfig, "--measured", bad.string(), "--out", scratch("bad_out").string(),
                "--discovery", "maybe"});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--discovery: must be on or off, got 'maybe'"), std::string::npos) << r.output;
  r = run_swum({"discrepancy", "--config", kConfig, "--measured", bad.string(), "--out", scratch("bad_out").string(),
                "--groups", "stator_damping,magic"});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--groups: unknown group 'magic' (known: stator_damping,"), std::string::npos) << r.output;
  r = run_swum({"discrepancy", "--config", kConfig, "--measured", bad.string(), "--out", scratch("bad_out").string(),
                "--discovery", "off", "--groups", "stator_damping"});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--groups: needs --discovery on"), std::string::npos) << r.output;
  r = run_swum({"discrepancy", "--config", kConfig, "--measured", bad.string(), "--out", scratch("bad_out").string(),
                "--groups", "mover_mass,mover_mass"});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--groups: group 'mover_mass' is named twice"), std::string::npos) << r.output;
  const fs::path out = scratch("never.csv");
  r = run_swum({"synth", "--config", kConfig, "--effect", "wear:speed=3", "--points", points_csv().string(), "--noise",
                "0.02", "--seed", "1", "--out", out.string()});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--effect: effect 'wear': 'speed=3' is not key=value"), std::string::npos) << r.output;
  r = run_swum({"synth", "--config", kConfig, "--effect", "friction", "--points", points_csv().string(), "--noise",
                "0.02", "--seed", "1", "--out", out.string()});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("unknown effect 'friction'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
  // Too few operating points to hold any out: refused before any fitting, naming the count.
  const fs::path few = scratch("few.csv");
  write(few, "amplitude_v,frequency_hz,load_n,speed_mm_s\n100,40000,0,12\n200,40100,0,30\n200,40100,0,31\n");
  r = run_swum({"discrepancy", "--config", kConfig, "--measured", few.string(), "--out", scratch("few_out").string()});
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("2 distinct operating points; the workflow needs at least 16"), std::string::npos)
      << r.output;
  r = run_swum({"discrepancy", "--config", kConfig, "--measured", few.string(), "--out", scratch("few_out").string(),
                "--effects", ","});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("--effects: empty name in ','"), std::string::npos) << r.output;
}

// Comma lists follow the one rule of docs/host.md ("Comma lists"): an empty name is refused (it
// used to be dropped silently here while calibrate refused it), blanks around a name are dropped.
TEST(SwumDiscrepancy, EmptyNamesInListsAreRefusedBeforeAnyWork) {
  const fs::path few = scratch("few_names.csv");
  write(few, "amplitude_v,frequency_hz,load_n,speed_mm_s\n100,40000,0,12\n200,40100,0,30\n");
  const std::string out = scratch("names_out").string();
  CliRun r = run_swum(
      {"discrepancy", "--config", kConfig, "--measured", few.string(), "--out", out, "--effects", "thermal,,wear"});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output, "swum: error: --effects: empty name in 'thermal,,wear'\n");
  r = run_swum(
      {"discrepancy", "--config", kConfig, "--measured", few.string(), "--out", out, "--quantities", "speed,"});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(r.output, "swum: error: --quantities: empty name in 'speed,'\n");
  // " thermal , wear" names thermal and wear: the run goes on to the file's check (two points).
  r = run_swum(
      {"discrepancy", "--config", kConfig, "--measured", few.string(), "--out", out, "--effects", " thermal , wear"});
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("2 distinct operating points"), std::string::npos) << r.output;
}

// `synth --quantities` reads its list with the same rule as `discrepancy --quantities` (it used
// to drop an empty name silently and refuse a name with a blank before it as unknown).
TEST(SwumSynth, QuantityListsFollowTheOneCommaListRule) {
  const fs::path two = scratch("two_points.csv");
  write(two, "amplitude_v,frequency_hz,load_n\n100,40000,0\n200,40100,0\n");
  const fs::path out = scratch("quantities.csv");
  fs::remove(out);
  for (const std::string list : {"speed,,tip_normal", "speed,", ",speed", ""}) {
    const CliRun r = run_swum(
        {"synth", "--config", kConfig, "--points", two.string(), "--quantities", list, "--out", out.string()});
    EXPECT_EQ(r.status, 2) << list << ": " << r.output;
    EXPECT_EQ(r.output, "swum: error: --quantities: empty name in '" + list + "'\n");
    EXPECT_FALSE(fs::exists(out)) << list;
  }
  const CliRun r = run_swum({"synth", "--config", kConfig, "--points", two.string(), "--noise", "0", "--quantities",
                             " speed, tip_normal ", "--out", out.string()});
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string text = swum::test::read_file(out);
  EXPECT_NE(text.find("\namplitude_v,frequency_hz,load_n,speed_mm_s,tip_normal_um\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("tip_tangential"), std::string::npos) << text;
  // Repeating the option adds to the list, as before.
  const CliRun repeated = run_swum({"synth", "--config", kConfig, "--points", two.string(), "--noise", "0",
                                    "--quantities", "speed", "--quantities", "tip_normal", "--out", out.string()});
  ASSERT_EQ(repeated.status, 0) << repeated.output;
  EXPECT_EQ(swum::test::read_file(out), text);
}

TEST(SwumSynth, LinearRepeatsAndNoiseFreeDataAreReproducible) {
  const fs::path a = scratch("a.csv"), b = scratch("b.csv");
  for (const fs::path& p : {a, b}) {
    const CliRun r = run_swum({"synth", "--config", kConfig, "--linear", "--effect", "thermal", "--points",
                               points_csv().string(), "--noise", "0.02", "--seed", "7", "--repeats", "2", "--out",
                               p.string()});
    ASSERT_EQ(r.status, 0) << r.output;
  }
  const std::string text = swum::test::read_file(a);
  EXPECT_EQ(text, swum::test::read_file(b));
  EXPECT_NE(text.find("amplitude_v,frequency_hz,load_n,time_s,speed_mm_s,tip_normal_um,tip_tangential_um"),
            std::string::npos);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2 + 64);  // comment, header, 2 x 32
}

// `synth --set/--scale` (src/formats/parameter_edit.h): any base parameter of the table moved on the
// command line, so the discovery step can be checked on a known answer.

// Four points on both sides of the softening peak, noise-free runs of them. One file per test:
// ctest runs the tests of this file side by side, and a file rewritten under a reader is a flake.
fs::path edit_points_csv() {
  const fs::path path = scratch(std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                                "_points.csv");
  write(path, "amplitude_v,frequency_hz,load_n\n200,40000,0\n300,39800,0\n300,40300,1\n400,40600,0\n");
  return path;
}

CliRun synth_edited(const std::string& config, const std::vector<std::string>& edits, const fs::path& out) {
  std::vector<std::string> args{"synth",   "--config", config,  "--points",  edit_points_csv().string(),
                                "--noise", "0",        "--out", out.string()};
  args.insert(args.end(), edits.begin(), edits.end());
  return run_swum(args);
}

// The file without its `# swum synth ...` comment line: the header and the rows.
std::string data_of(const fs::path& path) {
  const std::string text = swum::test::read_file(path);
  EXPECT_EQ(text.rfind("# swum synth ", 0), 0u) << text;
  return text.substr(text.find('\n') + 1);
}

// The speed_mm_s column of a noise-free synth file (columns: amplitude_v, frequency_hz, load_n, speed_mm_s, ...).
std::vector<double> speeds_of(const fs::path& path) {
  std::istringstream lines(data_of(path));
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line.rfind("amplitude_v,frequency_hz,load_n,speed_mm_s,", 0), 0u) << line;
  std::vector<double> speeds;
  while (std::getline(lines, line)) {
    std::istringstream cells(line);
    std::string cell;
    for (int column = 0; column < 4; ++column) std::getline(cells, cell, ',');
    speeds.push_back(std::stod(cell));
  }
  return speeds;
}

TEST(SwumSynth, ScaleMovesTheDataAndTheCommentLineSaysHow) {
  const fs::path plain = scratch("unscaled.csv"), scaled = scratch("scaled.csv");
  CliRun r = synth_edited(kConfig, {}, plain);
  ASSERT_EQ(r.status, 0) << r.output;
  r = synth_edited(kConfig, {"--scale", "stator.damping_l1_n_s_m=1.4", "--scale", " stator.damping_b2_n_s_m = 1.4"},
                   scaled);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(swum::test::read_file(scaled).find(
                " --scale stator.damping_l1_n_s_m=1.4 --scale stator.damping_b2_n_s_m=1.4 --noise "),
            std::string::npos)
      << swum::test::read_file(scaled);
  // 40 % more modal damping: smaller tip ellipses, slower at every point, by far more than any rounding.
  const std::vector<double> before = speeds_of(plain), after = speeds_of(scaled);
  ASSERT_EQ(before.size(), 4u);
  ASSERT_EQ(after.size(), 4u);
  for (std::size_t i = 0; i < before.size(); ++i) {
    EXPECT_LT(after[i], before[i] - 5.0) << "point " << i << ": " << before[i] << " -> " << after[i];
  }
}

TEST(SwumSynth, SetIsTheSameAsEditingTheConfigAndEditsApplyInCommandLineOrder) {
  std::string config = swum::test::read_file(kConfig);
  const std::string line = "preload_n = 24.8";
  ASSERT_NE(config.find(line), std::string::npos);
  config.replace(config.find(line), line.size(), "preload_n = 26.0");
  const fs::path edited_config = scratch("preload_26.toml");
  write(edited_config, config);
  const fs::path from_file = scratch("preload_file.csv"), from_set = scratch("preload_set.csv");
  CliRun r = synth_edited(edited_config.string(), {}, from_file);
  ASSERT_EQ(r.status, 0) << r.output;
  r = synth_edited(kConfig, {"--set", "contact.preload_n=26"}, from_set);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(data_of(from_set), data_of(from_file));
  EXPECT_NE(swum::test::read_file(from_set).find(" --set contact.preload_n=26 --noise "), std::string::npos);
  // 20 x 1.3 = 26: the same rows; the other way round 20 wins.
  const fs::path set_then_scale = scratch("set_then_scale.csv"), scale_then_set = scratch("scale_then_set.csv");
  r = synth_edited(kConfig, {"--set", "contact.preload_n=20", "--scale", "contact.preload_n=1.3"}, set_then_scale);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(data_of(set_then_scale), data_of(from_file));
  r = synth_edited(kConfig, {"--scale", "contact.preload_n=1.3", "--set", "contact.preload_n=20"}, scale_then_set);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(data_of(scale_then_set), data_of(from_file));
  EXPECT_NE(
      swum::test::read_file(scale_then_set).find("--scale contact.preload_n=1.3 --set contact.preload_n=20 --noise"),
      std::string::npos);
}

TEST(SwumSynth, BadSetAndScaleItemsAreOneLineUsageErrorsAndWriteNothing) {
  const fs::path out = scratch("never_edited.csv");
  fs::remove(out);
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {{"--set", "contact.preload_n"}, "--set 'contact.preload_n': expected SECTION.KEY=VALUE (no '=')"},
      {{"--scale", "contact.preload=2"},
       "--scale 'contact.preload=2': unknown parameter 'contact.preload' (keys of contact: preload_n, "},
      {{"--set", "contacts.preload_n=2"},
       "--set 'contacts.preload_n=2': unknown parameter 'contacts.preload_n' (sections: stator, contact, "},
      {{"--set", "contact.preload_n=26N"}, "--set 'contact.preload_n=26N': '26N' is not a number"},
      {{"--scale", "contact.preload_n=inf"}, "--scale 'contact.preload_n=inf': 'inf' is not finite"},
      {{"--scale", "contact.preload_application=2"},
       "--scale 'contact.preload_application=2': contact.preload_application is a choice ("},
      {{"--scale", "effects.wear.enabled=2"},
       "--scale 'effects.wear.enabled=2': effects.wear.enabled is true or false"},
      {{"--set", "contact.preload_n=-1"}, "--set 'contact.preload_n=-1': contact.preload_n = -1 is out of range ["},
      {{"--scale", "stator.damping_l1_n_s_m=1e6"},
       "--scale 'stator.damping_l1_n_s_m=1e6': stator.damping_l1_n_s_m = 39000000 (39 x 1e+06) is out of range ["},
      // What one key's range cannot say: validate_parameters over the whole set.
      {{"--set", "stator.geometry=explicit", "--set", "stator.half_height_mm=70"},
       "--set/--scale: stator.half_height_mm must be smaller than stator.length_mm"},
  };
  for (const auto& [edits, message] : cases) {
    SCOPED_TRACE(edits.back());
    const CliRun r = synth_edited(kConfig, edits, out);
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_EQ(r.output.rfind("swum: error: " + message, 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(out.string() + ".partial"));
  }
}

}  // namespace
