// The spreads file of `swum population`: the example in config/ loads, and every reject is one
// message naming the file, the line and what is wrong.
#include "formats/spread_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "formats/parameter_file.h"
#include "test_paths.h"

namespace swum {
namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

MotorParameters nominal() {
  const std::string path = swum::test::source_path("config/li2019.toml");
  return parse_motor_parameters(read(path), path);
}

// The message of parsing `text` as spreads.toml, or "" when it loads.
std::string error_of(const std::string& text) {
  try {
    (void)parse_parameter_spreads(text, "spreads.toml", nominal());
  } catch (const ParameterError& e) {
    return e.what();
  }
  return "";
}

TEST(SpreadFile, TheExampleLoadsInParameterTableOrderWithRangesInsideTheDocumentedOnes) {
  const std::string path = swum::test::source_path("config/population.toml");
  const auto spreads = parse_parameter_spreads(read(path), path, nominal());
  ASSERT_GE(spreads.size(), 8u);
  std::size_t previous = 0;
  const auto specs = parameter_specs();
  for (const ParameterSpread& s : spreads) {
    const auto index = static_cast<std::size_t>(s.spec - specs.data());
    EXPECT_GE(index, previous) << s.spec->name();
    previous = index;
    EXPECT_LE(s.low, s.nominal) << s.spec->name();
    EXPECT_GE(s.high, s.nominal) << s.spec->name();
    EXPECT_GE(s.low, s.spec->min_value) << s.spec->name();
    EXPECT_LE(s.high, s.spec->max_value) << s.spec->name();
    EXPECT_GT(s.line, 0);
  }
}

TEST(SpreadFile, PercentAndAbsoluteFormsGiveTheSameRange) {
  const auto spreads = parse_parameter_spreads(
      "[contact]\n"
      "preload_n = { distribution = \"normal\", sigma_percent = 10, truncate = 2 }\n"
      "friction_coefficient = { distribution = \"uniform\", half_width = 0.05 }\n"
      "[mover]\n"
      "mass_kg = { distribution = \"uniform\", min = 0.19, max = 0.21 }\n",
      "s.toml", nominal());
  ASSERT_EQ(spreads.size(), 3u);
  EXPECT_EQ(spreads[0].spec->name(), "contact.preload_n");
  EXPECT_DOUBLE_EQ(spreads[0].sigma, 2.48);
  EXPECT_DOUBLE_EQ(spreads[0].low, 24.8 - 2 * 2.48);
  EXPECT_EQ(spreads[0].distribution, SpreadDistribution::normal);
  EXPECT_DOUBLE_EQ(spreads[1].low, 0.30);
  EXPECT_DOUBLE_EQ(spreads[1].high, 0.40);
  EXPECT_DOUBLE_EQ(spreads[2].low, 0.19);
  EXPECT_EQ(spreads[2].distribution, SpreadDistribution::uniform);
  EXPECT_EQ(spreads[0].line, 2);
}

TEST(SpreadFile, AnEmptyFileVariesNothing) {
  EXPECT_TRUE(parse_parameter_spreads("# nothing varies\n", "s.toml", nominal()).empty());
}

TEST(SpreadFile, RejectsAreOneLineWithFileLineAndWhat) {
  struct Case {
    const char* text;
    const char* expected;
  };
  const Case cases[] = {
      {"[contact]\npreload = { distribution = \"normal\", sigma = 1 }\n",
       "spreads.toml:2: unknown parameter contact.preload"},
      {"[contact]\npreload_n = { distribution = \"gauss\", sigma = 1 }\n",
       "spreads.toml:2: contact.preload_n: unknown distribution"},
      {"[contact]\npreload_n = { distribution = \"normal\", sigma = -1 }\n",
       "spreads.toml:2: contact.preload_n: sigma -1 is negative"},
      {"[contact]\npreload_n = { distribution = \"normal\" }\n", "give exactly one of sigma"},
      {"[contact]\npreload_n = { distribution = \"normal\", sigma = 1, sigma_percent = 2 }\n",
       "give exactly one of sigma"},
      {"[contact]\npreload_n = { distribution = \"normal\", sigma = 1, min = 2 }\n", "unknown key min for a normal"},
      {"[contact]\npreload_n = { distribution = \"normal\", sigma = 1, truncate = 0.1 }\n", "truncate 0.1 is outside"},
      {"[contact]\npreload_n = { distribution = \"normal\", sigma = 10 }\n",
       "spreads.toml:2: contact.preload_n: draws range over [-5.2, 54.8] N, outside the parameter's range [0, 100000]"},
      {"[contact]\nfriction_coefficient = { distribution = \"uniform\", min = 0.4, max = 0.3 }\n",
       "min 0.4 is above max 0.3"},
      {"[contact]\nfriction_coefficient = { distribution = \"uniform\", min = 0.4 }\n", "min and max go together"},
      {"[contact]\nfriction_coefficient = { sigma = 1 }\n", "distribution missing"},
      {"[contact]\nfriction_coefficient = 0.3\n", "spreads.toml:2: contact.friction_coefficient must be a table"},
      {"[contact]\ntangential_stiffness_n_m = { distribution = \"normal\", sigma_percent = 5 }\n[mover]\n"
       "guide_sign_smoothing_m_s = { distribution = \"uniform\", half_width_percent = 5 }\n"
       "gravity_m_s2 = { distribution = \"normal\", sigma = \"big\" }\n",
       "spreads.toml:5: mover.gravity_m_s2: sigma must be a number"},
      {"[numerics]\ntime_step_ns = { distribution = \"normal\", sigma = 1 }\n",
       "spreads.toml:1: unknown section [numerics]"},
      {"[stator]\ngeometry = { distribution = \"normal\", sigma = 1 }\n",
       "stator.geometry is not a real-valued parameter"},
      {"[stator]\nlength_mm = { distribution = \"normal\", sigma = 0.1 }\n", "stator.length_mm is unused"},
      {"[stator]\ntip_lever_over_length = { distribution = \"normal\", sigma_percent = 1 }\n",
       "percentage of the nominal value, which is 0"},
      {"[contact\n", "spreads.toml:1: TOML syntax error"},
  };
  for (const Case& c : cases) {
    const std::string message = error_of(c.text);
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.text << "\n -> " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace swum
