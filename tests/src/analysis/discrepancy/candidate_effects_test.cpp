// The candidate-effect library: every effect is a table section, neutral = the baseline,
// and `NAME[:key=value,...]` arguments with clear errors.
#include "analysis/discrepancy/candidate_effects.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "formats/parameter_file.h"

namespace swum {
namespace {

std::string error_of(const std::string& argument) {
  MotorParameters p;
  try {
    apply_effect_argument(p, argument);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(CandidateEffects, EveryEffectHasItsTableSectionAndPlausibleRange) {
  ASSERT_EQ(candidate_effects().size(), 6u);
  for (const auto& e : candidate_effects()) {
    const ParameterSpec& spec = effect_free_spec(e);
    EXPECT_GE(e.neutral, e.lower) << e.name;
    EXPECT_LE(e.neutral, e.upper) << e.name;
    EXPECT_GE(e.plausible_low, spec.min_value) << e.name;
    EXPECT_LE(e.plausible_high, spec.max_value) << e.name;
    EXPECT_LT(e.plausible_low, e.plausible_high) << e.name;
    EXPECT_NE(e.typical, 0.0) << e.name;
    MotorParameters p;
    EXPECT_FALSE(effect_enabled(p, e));
    enable_effect(p, e, e.plausible_low);
    EXPECT_TRUE(effect_enabled(p, e));
    EXPECT_EQ(effect_value(p, e), e.plausible_low);
  }
}

TEST(CandidateEffects, BareNameUsesTheDocumentedDefaultAndKeysOverride) {
  MotorParameters p;
  apply_effect_argument(p, "thermal");
  EXPECT_TRUE(p.effects.thermal.enabled);
  EXPECT_EQ(p.effects.thermal.thermal_resistance_k_per_w, ThermalEffect{}.thermal_resistance_k_per_w);
  apply_effect_argument(p, "wear:friction_change=0.3,run_in_distance_m=5");
  EXPECT_TRUE(p.effects.wear.enabled);
  EXPECT_EQ(p.effects.wear.friction_change, 0.3);
  EXPECT_EQ(p.effects.wear.run_in_distance_m, 5.0);
}

TEST(CandidateEffects, BadArgumentsAreNamed) {
  EXPECT_EQ(error_of("heat"), "unknown effect 'heat' (known: electroelastic, thermal, wear, preload, "
                              "guide_friction, amplifier_droop)");
  EXPECT_NE(error_of("thermal:tau=3").find("'tau=3' is not key=value with a key of effects.thermal"),
            std::string::npos);
  EXPECT_NE(error_of("thermal:time_constant_s").find("is not key=value"), std::string::npos);
  EXPECT_NE(error_of("thermal:time_constant_s=20,").find("'' is not key=value"), std::string::npos);
  EXPECT_EQ(error_of("preload:preload_factor=abc"), "effect 'preload': preload_factor = 'abc' is not a finite number");
  EXPECT_NE(error_of("preload:preload_factor=99").find("out of range"), std::string::npos);
  EXPECT_NE(error_of("thermal:").find("expected key=value"), std::string::npos);
}

TEST(CandidateEffects, EffectTablesRoundTripThroughTheParameterFile) {
  MotorParameters p;
  apply_effect_argument(p, "amplifier_droop:source_resistance_ohm=75");
  apply_effect_argument(p, "guide_friction");
  const MotorParameters again = parse_motor_parameters(format_motor_parameters(p), "augmented");
  EXPECT_TRUE(again.effects.amplifier_droop.enabled);
  EXPECT_EQ(again.effects.amplifier_droop.source_resistance_ohm, 75.0);
  EXPECT_TRUE(again.effects.guide_friction.enabled);
  EXPECT_FALSE(again.effects.thermal.enabled);
  const MotorParameters nested = parse_motor_parameters("[effects.thermal]\nenabled = true\ntime_constant_s = 12\n",
                                                        "nested.toml");
  EXPECT_EQ(nested.effects.thermal.time_constant_s, 12.0);
  EXPECT_THROW((void)parse_motor_parameters("[effects.heat]\nenabled = true\n", "x.toml"), ParameterError);
  EXPECT_THROW((void)parse_motor_parameters("[effects.thermal]\nenabled = 3\n", "x.toml"), ParameterError);
}

}  // namespace
}  // namespace swum
