#include "model/parameters.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include "test_paths.h"

namespace swum {
namespace {

TEST(ParameterSpecs, KeysAreUniqueAndDefaultsValid) {
  std::set<std::string> keys;
  for (const auto& spec : parameter_specs()) {
    EXPECT_TRUE(keys.insert(std::string(spec.section) + "." + std::string(spec.key)).second) << spec.key;
    EXPECT_FALSE(spec.description.empty()) << spec.key;
    EXPECT_LE(spec.min_value, spec.max_value) << spec.key;
  }
  EXPECT_NO_THROW(validate_parameters(MotorParameters{}, "defaults"));
  EXPECT_NE(find_parameter_spec("contact", "preload_n"), nullptr);
  EXPECT_EQ(find_parameter_spec("contact", "nope"), nullptr);
}

TEST(ParameterSpecs, AccessorsRoundTrip) {
  MotorParameters p{};
  const auto* spec = find_parameter_spec("mover", "mass_kg");
  ASSERT_NE(spec, nullptr);
  spec->set(p, 0.5);
  EXPECT_EQ(p.mover.mass_kg, 0.5);
  EXPECT_EQ(spec->get(p), 0.5);
  const auto* choice = find_parameter_spec("options", "paper_voltage_axis");
  ASSERT_NE(choice, nullptr);
  choice->set(p, 1.0);
  EXPECT_EQ(p.options.paper_voltage_axis, PaperVoltageAxis::amplitude);
  EXPECT_EQ(find_parameter_spec("options", "voltage_convention"), nullptr);
}

TEST(ValidateParameters, RejectsNanAndOutOfRangeNamingTheKey) {
  MotorParameters p{};
  p.contact.preload_n = std::numeric_limits<double>::quiet_NaN();
  try {
    validate_parameters(p, "unit-test");
    FAIL() << "no throw";
  } catch (const ParameterError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("unit-test"), std::string::npos) << msg;
    EXPECT_NE(msg.find("contact.preload_n"), std::string::npos) << msg;
  }
  p = MotorParameters{};
  p.mover.mass_kg = -1.0;
  EXPECT_THROW(validate_parameters(p, "x"), ParameterError);
}

TEST(ParametersDoc, DocsFileMatchesTheTable) {
  std::ifstream in(swum::test::source_path("docs/parameters.md"));
  ASSERT_TRUE(in.good()) << "docs/parameters.md missing";
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), render_parameters_markdown())
      << "docs/parameters.md is out of date: regenerate it from render_parameters_markdown()";
}

}  // namespace
}  // namespace swum
