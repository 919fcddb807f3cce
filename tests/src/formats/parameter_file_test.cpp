#include "formats/parameter_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "model/motor_model.h"
#include "test_paths.h"

namespace swum {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The message of the ParameterError thrown for `text`.
std::string error_of(const std::string& text) {
  try {
    (void)parse_motor_parameters(text, "test.toml");
  } catch (const ParameterError& e) {
    return e.what();
  }
  return "<no error>";
}

TEST(ParameterFile, EmptyTextGivesDefaults) {
  const auto p = parse_motor_parameters("", "empty.toml");
  EXPECT_EQ(p.contact.preload_n, MotorParameters{}.contact.preload_n);
}

TEST(ParameterFile, CalibratedConfigIsReferencePlusTheCalibration) {
  auto p = parse_motor_parameters(read_text(swum::test::source_path("config/li2019.toml")), "li2019.toml");
  EXPECT_EQ(p.options.paper_voltage_axis, PaperVoltageAxis::amplitude);
  EXPECT_EQ(p.contact.preload_application, PreloadApplication::back_end_constant);
  EXPECT_GT(p.contact.tangential_stiffness_n_m, 0.0);
  EXPECT_EQ(p.mover.guide_friction_model, GuideFrictionModel::implicit_coulomb);
  // Undo the calibrated keys: what remains is the model_spec §9 reference set (the defaults).
  const MotorParameters d{};
  p.options.paper_voltage_axis = d.options.paper_voltage_axis;
  p.contact.preload_application = d.contact.preload_application;
  p.contact.tangential_stiffness_n_m = d.contact.tangential_stiffness_n_m;
  p.mover.guide_friction_model = d.mover.guide_friction_model;
  p.stator.substrate_thickness_mm = d.stator.substrate_thickness_mm;
  p.stator.c1111_pa = d.stator.c1111_pa;
  EXPECT_NEAR(p.numerics.time_step_ns, 1e9 / (48 * 40000.0),
              1e-9);  // the accuracy contract's fewest steps, docs/performance.md
  p.numerics.time_step_ns = d.numerics.time_step_ns;
  EXPECT_EQ(format_motor_parameters(p), format_motor_parameters(d));
  const MotorModel model(
      parse_motor_parameters(read_text(swum::test::source_path("config/li2019.toml")), "li2019.toml"));
  EXPECT_NEAR(model.constants().f_l1_hz, 39516.0, 0.002 * 39516.0);  // paper natural frequencies
  EXPECT_NEAR(model.constants().f_b2_hz, 39469.0, 0.002 * 39469.0);
}

TEST(ParameterFile, LiteralConfigHasLiteralLever) {
  const auto p = parse_motor_parameters(read_text(swum::test::source_path("config/li2019_literal.toml")),
                                        "li2019_literal.toml");
  const MotorModel model(p);
  EXPECT_NEAR(model.constants().g_t, 4.07, 0.01);
  EXPECT_EQ(p.options.paper_voltage_axis, PaperVoltageAxis::peak_to_peak);
  // The calibration terms are off: the paper as printed.
  EXPECT_EQ(p.contact.preload_application, PreloadApplication::both_ends);
  EXPECT_EQ(p.contact.tangential_stiffness_n_m, 0.0);
  EXPECT_EQ(p.mover.guide_friction_model, GuideFrictionModel::smoothed_sign);
  EXPECT_DOUBLE_EQ(model.constants().g_n, 2.0);
}

// The long-run configuration is the calibrated motor with the stator temperature on: nothing
// else may drift away from li2019.toml.
TEST(ParameterFile, ThermalConfigIsTheCalibratedMotorWithTemperature) {
  const auto calibrated = parse_motor_parameters(read_text(swum::test::source_path("config/li2019.toml")),
                                                 "li2019.toml");
  auto thermal = parse_motor_parameters(read_text(swum::test::source_path("config/li2019_thermal.toml")),
                                        "li2019_thermal.toml");
  EXPECT_TRUE(thermal.effects.thermal.enabled);
  EXPECT_EQ(thermal.effects.thermal.time_constant_s, 30.0);
  EXPECT_LT(thermal.effects.thermal.stiffness_coefficient_per_k, 0.0);  // the resonance falls when hot
  thermal.effects.thermal = calibrated.effects.thermal;
  EXPECT_EQ(format_motor_parameters(thermal), format_motor_parameters(calibrated));
}

TEST(ParameterFile, RoundTrip) {
  MotorParameters p{};
  p.contact.preload_n = 12.5;
  p.options.electrode_diagonals = ElectrodeDiagonals::swapped;
  p.numerics.quadrature_points = 64;
  const auto q = parse_motor_parameters(format_motor_parameters(p), "roundtrip");
  EXPECT_EQ(format_motor_parameters(q), format_motor_parameters(p));
  EXPECT_EQ(q.numerics.time_step_ns, p.numerics.time_step_ns);
}

TEST(ParameterFile, IntegerAcceptedForReal) {
  const auto p = parse_motor_parameters("[contact]\npreload_n = 20\n", "t");
  EXPECT_EQ(p.contact.preload_n, 20.0);
}

TEST(ParameterFile, UnknownKeyNamesKeyAndLine) {
  const auto msg = error_of("[contact]\npreload_n = 20\npreloud_n = 3\n");
  EXPECT_NE(msg.find("test.toml:3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("contact.preloud_n"), std::string::npos) << msg;
  EXPECT_NE(msg.find("unknown key"), std::string::npos) << msg;
}

// One C0 (docs/parameters.md): the droop effect reads the stator's clamped capacitance. Files
// written before (every key of the table, the effect's C0 among them) still read when the two
// agree; a file that sets them apart is refused, naming both.
TEST(ParameterFile, TheDroopEffectsOldC0KeyMustRepeatTheStators) {
  const std::string old_output = "[stator]\nclamped_capacitance_nf = 12.5\n"
                                 "[effects.amplifier_droop]\nenabled = true\nclamped_capacitance_nf = 12.5\n";
  const auto p = parse_motor_parameters(old_output, "old.toml");
  EXPECT_EQ(p.stator.clamped_capacitance_nf, 12.5);
  EXPECT_TRUE(p.effects.amplifier_droop.enabled);
  EXPECT_EQ(parse_motor_parameters("[effects.amplifier_droop]\nclamped_capacitance_nf = 10.0\n", "t")
                .stator.clamped_capacitance_nf,
            10.0);  // the default of both
  EXPECT_EQ(error_of("[effects.amplifier_droop]\nclamped_capacitance_nf = 20\n"),
            "test.toml:2: effects.amplifier_droop.clamped_capacitance_nf = 20 differs from "
            "stator.clamped_capacitance_nf = 10: the droop effect uses the stator's C0; set only [stator] "
            "clamped_capacitance_nf");
  EXPECT_NE(error_of("[effects.amplifier_droop]\nclamped_capacitance_nf = -1\n")
                .find("test.toml:2: effects.amplifier_droop.clamped_capacitance_nf"),
            std::string::npos);
  // Written today, the key is gone: the stator's is the one C0.
  const std::string written = format_motor_parameters(p);
  EXPECT_NE(written.find("clamped_capacitance_nf = 12.5"), std::string::npos) << written;
  EXPECT_EQ(written.find("clamped_capacitance_nf"), written.rfind("clamped_capacitance_nf")) << written;
}

TEST(ParameterFile, UnknownSection) {
  const auto msg = error_of("[contakt]\npreload_n = 20\n");
  EXPECT_NE(msg.find("unknown section [contakt]"), std::string::npos) << msg;
}

TEST(ParameterFile, OutOfRangeNamesKeyAndRange) {
  const auto msg = error_of("[mover]\nmass_kg = -0.2\n");
  EXPECT_NE(msg.find("mover.mass_kg"), std::string::npos) << msg;
  EXPECT_NE(msg.find("out of range"), std::string::npos) << msg;
  EXPECT_NE(msg.find("allowed: ["), std::string::npos) << msg;
  EXPECT_NE(msg.find(":2"), std::string::npos) << msg;
}

TEST(ParameterFile, NanAndInfRejected) {
  for (const char* v : {"nan", "inf", "-inf"}) {
    const auto msg = error_of(std::string("[contact]\nstiffness_n_m = ") + v + "\n");
    EXPECT_NE(msg.find("contact.stiffness_n_m"), std::string::npos) << msg;
    EXPECT_NE(msg.find("finite"), std::string::npos) << msg;
  }
}

TEST(ParameterFile, WrongTypeNamesKey) {
  auto msg = error_of("[contact]\npreload_n = \"24.8\"\n");
  EXPECT_NE(msg.find("contact.preload_n must be a number"), std::string::npos) << msg;
  msg = error_of("[options]\npaper_voltage_axis = 2\n");
  EXPECT_NE(msg.find("options.paper_voltage_axis must be a string"), std::string::npos) << msg;
  msg = error_of("[options]\npaper_voltage_axis = \"rms\"\n");
  EXPECT_NE(msg.find("unknown value \"rms\""), std::string::npos) << msg;
  EXPECT_NE(msg.find("\"peak_to_peak\""), std::string::npos) << msg;
  msg = error_of("[numerics]\nquadrature_points = 10.5\n");
  EXPECT_NE(msg.find("numerics.quadrature_points must be an integer"), std::string::npos) << msg;
  msg = error_of("contact = 3\n");
  EXPECT_NE(msg.find("must be a table"), std::string::npos) << msg;
}

// A file written before issue 34 says options.voltage_convention: it must not load (its inputs
// would silently change meaning), and the one line names the key, the file and the new key.
TEST(ParameterFile, TheRetiredVoltageConventionFailsNamingTheNewKey) {
  for (const char* value : {"\"amplitude\"", "\"peak_to_peak\""}) {
    const auto msg = error_of(std::string("[options]\nvoltage_convention = ") + value + "\n");
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    EXPECT_NE(msg.find("test.toml:2"), std::string::npos) << msg;
    EXPECT_NE(msg.find("options.voltage_convention is retired"), std::string::npos) << msg;
    EXPECT_NE(msg.find("options.paper_voltage_axis"), std::string::npos) << msg;
  }
}

TEST(ParameterFile, SyntaxErrorHasLine) {
  const auto msg = error_of("[contact]\npreload_n = = 3\n");
  EXPECT_NE(msg.find("test.toml:2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("syntax"), std::string::npos) << msg;
}

}  // namespace
}  // namespace swum
