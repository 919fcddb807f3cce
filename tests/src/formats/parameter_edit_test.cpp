// "SECTION.KEY=VALUE" items of `swum synth --set/--scale` (src/formats/parameter_edit.h): any key
// of the table, numbers, names of booleans and choices, and one-line refusals naming the option,
// the text and the key.
#include "formats/parameter_edit.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace swum {
namespace {

// The message of the std::invalid_argument `f` throws ("" if it throws none).
template <typename F>
std::string refusal(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

std::string parse_refusal(ParameterEditKind kind, const std::string& text) {
  return refusal([&] { (void)parse_parameter_edit(kind, text); });
}

TEST(ParameterEdit, SetWritesAndScaleMultipliesAnyKeyOfTheTable) {
  MotorParameters p;
  apply_parameter_edit(p, parse_parameter_edit(ParameterEditKind::set, "contact.preload_n=26"));
  EXPECT_EQ(p.contact.preload_n, 26.0);
  apply_parameter_edit(p, parse_parameter_edit(ParameterEditKind::scale, " stator.damping_l1_n_s_m = 1.5 "));
  EXPECT_EQ(p.stator.damping_l1_n_s_m, 39.0 * 1.5);
  // Sections with a dot: the key is what follows the last one.
  const ParameterEdit tau = parse_parameter_edit(ParameterEditKind::set, "effects.thermal.time_constant_s=+12");
  EXPECT_EQ(tau.spec->name(), "effects.thermal.time_constant_s");
  EXPECT_EQ(tau.text, "effects.thermal.time_constant_s=+12");
  apply_parameter_edit(p, tau);
  EXPECT_EQ(p.effects.thermal.time_constant_s, 12.0);
  // Integers, scaled to a whole number.
  apply_parameter_edit(p, parse_parameter_edit(ParameterEditKind::scale, "numerics.quadrature_points=2"));
  EXPECT_EQ(p.numerics.quadrature_points, 800);
  // A 0 cannot be scaled: the change would silently not be there.
  try {
    apply_parameter_edit(p, parse_parameter_edit(ParameterEditKind::scale, "contact.tangential_stiffness_n_m=3"));
    ADD_FAILURE() << "scaling a 0 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "--scale 'contact.tangential_stiffness_n_m=3': contact.tangential_stiffness_n_m is 0, so scaling it "
                 "changes nothing; give a value with --set");
  }
  EXPECT_EQ(p.contact.tangential_stiffness_n_m, 0.0);
  EXPECT_EQ(parse_parameter_edit(ParameterEditKind::scale, "stator.damping_b2_n_s_m= 1.4").text,
            "stator.damping_b2_n_s_m=1.4");
}

TEST(ParameterEdit, SetTakesBooleansAndChoicesByTheirNames) {
  MotorParameters p;
  apply_parameter_edit(p, parse_parameter_edit(ParameterEditKind::set, "options.paper_voltage_axis=amplitude"));
  EXPECT_EQ(p.options.paper_voltage_axis, PaperVoltageAxis::amplitude);
  apply_parameter_edit(p, parse_parameter_edit(ParameterEditKind::set, "stator.geometry=\"explicit\""));
  EXPECT_EQ(p.stator.geometry, GeometryMode::explicit_size);
  apply_parameter_edit(p, parse_parameter_edit(ParameterEditKind::set, "effects.wear.enabled=true"));
  EXPECT_TRUE(p.effects.wear.enabled);
  EXPECT_EQ(parse_refusal(ParameterEditKind::set, "effects.wear.enabled=1"),
            "--set 'effects.wear.enabled=1': effects.wear.enabled takes true or false, not '1'");
  EXPECT_EQ(parse_refusal(ParameterEditKind::set, "options.paper_voltage_axis=vpp"),
            "--set 'options.paper_voltage_axis=vpp': options.paper_voltage_axis takes one of \"peak_to_peak\", "
            "\"amplitude\", not 'vpp'");
}

TEST(ParameterEdit, BadItemsAreOneLineRefusalsNamingOptionAndText) {
  EXPECT_EQ(parse_refusal(ParameterEditKind::set, "contact.preload_n"),
            "--set 'contact.preload_n': expected SECTION.KEY=VALUE (no '=')");
  EXPECT_EQ(parse_refusal(ParameterEditKind::scale, "contact.preload_n:2"),
            "--scale 'contact.preload_n:2': expected SECTION.KEY=FACTOR (no '=')");
  // An unknown key of a known section lists the section's keys; an unknown section the sections.
  const std::string key = parse_refusal(ParameterEditKind::set, "contact.preload=26");
  EXPECT_EQ(key.rfind("--set 'contact.preload=26': unknown parameter 'contact.preload' (keys of contact: preload_n, "
                      "stiffness_n_m, ",
                      0),
            0u)
      << key;
  const std::string section = parse_refusal(ParameterEditKind::scale, "preload_n=2");
  EXPECT_EQ(
      section.rfind("--scale 'preload_n=2': unknown parameter 'preload_n' (sections: stator, contact, mover, ", 0), 0u)
      << section;
  EXPECT_NE(section.find("effects.thermal"), std::string::npos) << section;
  EXPECT_EQ(parse_refusal(ParameterEditKind::set, "contact.preload_n=26N"),
            "--set 'contact.preload_n=26N': '26N' is not a number");
  EXPECT_EQ(parse_refusal(ParameterEditKind::set, "contact.preload_n="),
            "--set 'contact.preload_n=': '' is not a number");
  EXPECT_EQ(parse_refusal(ParameterEditKind::scale, "contact.preload_n=inf"),
            "--scale 'contact.preload_n=inf': 'inf' is not finite");
  EXPECT_EQ(parse_refusal(ParameterEditKind::scale, "contact.preload_n=nan"),
            "--scale 'contact.preload_n=nan': 'nan' is not finite");
  EXPECT_EQ(parse_refusal(ParameterEditKind::scale, "stator.geometry=2"),
            "--scale 'stator.geometry=2': stator.geometry is a choice (\"from_frequencies\", \"explicit\"), not a "
            "number to scale; give it with --set");
  EXPECT_EQ(parse_refusal(ParameterEditKind::scale, "effects.thermal.enabled=1"),
            "--scale 'effects.thermal.enabled=1': effects.thermal.enabled is true or false, not a number to scale; "
            "give it with --set");
}

TEST(ParameterEdit, AResultOutsideTheRangeIsRefusedNamingTheKeyAndLeavesTheParameters) {
  MotorParameters p;
  const auto apply = [&](ParameterEditKind kind, const std::string& text) {
    return refusal([&] { apply_parameter_edit(p, parse_parameter_edit(kind, text)); });
  };
  const std::string set = apply(ParameterEditKind::set, "contact.preload_n=-1");
  EXPECT_EQ(set.rfind("--set 'contact.preload_n=-1': contact.preload_n = -1 is out of range [", 0), 0u) << set;
  const std::string scale = apply(ParameterEditKind::scale, "stator.damping_l1_n_s_m=-2");
  EXPECT_EQ(scale.rfind("--scale 'stator.damping_l1_n_s_m=-2': stator.damping_l1_n_s_m = -78 (39 x -2) is out of "
                        "range [",
                        0),
            0u)
      << scale;
  EXPECT_EQ(apply(ParameterEditKind::scale, "stator.c1111_pa=1e300"),
            "--scale 'stator.c1111_pa=1e300': stator.c1111_pa = -inf (-2.8856e+17 x 1e+300) is not finite");
  EXPECT_EQ(apply(ParameterEditKind::set, "numerics.quadrature_points=400.5"),
            "--set 'numerics.quadrature_points=400.5': numerics.quadrature_points = 400.5 is not a whole number");
  EXPECT_EQ(p.contact.preload_n, MotorParameters{}.contact.preload_n);
  EXPECT_EQ(p.stator.damping_l1_n_s_m, MotorParameters{}.stator.damping_l1_n_s_m);
  EXPECT_EQ(p.numerics.quadrature_points, MotorParameters{}.numerics.quadrature_points);
}

}  // namespace
}  // namespace swum
