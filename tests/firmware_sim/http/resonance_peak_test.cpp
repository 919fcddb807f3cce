// firmware_sim/http/resonance_peak.h with config/li2019.toml: the free stator's peaks are finite and
// in the motor's band, soften with the drive amplitude, are those of the whole volt (at least
// 1 V), and move with the stator temperature only when the thermal effect is on (it is off in
// li2019.toml), through both the stiffness and the damping factor.
#include "http/resonance_peak.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "../emu_test_support.h"
#include "core/scenario_player.h"

namespace swum::emu {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(ResonancePeak, PeaksAreFiniteAndBetween30And50Khz) {
  ResonancePeak peak(test::li2019_model());
  for (const double amplitude_v : {1.0, 50.0, 200.0, 400.0}) {
    const ResonanceEstimate e = peak.at(amplitude_v, kReferenceAmbientC);
    EXPECT_EQ(e.amplitude_v, amplitude_v);
    ASSERT_TRUE(std::isfinite(e.normal_peak_hz)) << amplitude_v;
    ASSERT_TRUE(std::isfinite(e.tangential_peak_hz)) << amplitude_v;
    EXPECT_GT(e.normal_peak_hz, 30e3) << amplitude_v;
    EXPECT_LT(e.normal_peak_hz, 50e3) << amplitude_v;
    EXPECT_GT(e.tangential_peak_hz, 30e3) << amplitude_v;
    EXPECT_LT(e.tangential_peak_hz, 50e3) << amplitude_v;
  }
}

TEST(ResonancePeak, PeaksSoftenFrom50To400V) {
  ResonancePeak peak(test::li2019_model());
  const ResonanceEstimate low = peak.at(50.0, kReferenceAmbientC);
  const ResonanceEstimate high = peak.at(400.0, kReferenceAmbientC);
  // Paper Fig. 9 (tests/src/analysis/free_stator/harmonic_balance_test.cpp): L1 ~280 Hz, B2 ~1 kHz lower.
  EXPECT_LT(high.normal_peak_hz, low.normal_peak_hz - 100.0);
  EXPECT_GT(high.normal_peak_hz, low.normal_peak_hz - 1000.0);
  EXPECT_LT(high.tangential_peak_hz, low.tangential_peak_hz - 300.0);
}

TEST(ResonancePeak, PeaksAreTheHarmonicBalanceBackboneAtTheWholeVolt) {
  ResonancePeak peak(test::li2019_model());
  const FreeStatorHarmonicBalance balance(test::li2019_model());
  const BackbonePoint expected = balance.backbone(123.0);
  const ResonanceEstimate e = peak.at(123.0, kReferenceAmbientC);
  EXPECT_EQ(e.normal_peak_hz, expected.normal_peak_hz);
  EXPECT_EQ(e.tangential_peak_hz, expected.tangential_peak_hz);
}

TEST(ResonancePeak, AmplitudeIsRoundedToTheNearestVolt) {
  ResonancePeak peak(test::li2019_model());
  const ResonanceEstimate at_100 = peak.at(100.0, kReferenceAmbientC);
  const ResonanceEstimate below = peak.at(100.4, kReferenceAmbientC);
  EXPECT_EQ(below.amplitude_v, 100.0);
  EXPECT_EQ(below.normal_peak_hz, at_100.normal_peak_hz);
  EXPECT_EQ(below.tangential_peak_hz, at_100.tangential_peak_hz);
  const ResonanceEstimate above = peak.at(100.6, kReferenceAmbientC);
  EXPECT_EQ(above.amplitude_v, 101.0);
  const ResonanceEstimate at_101 = peak.at(101.0, kReferenceAmbientC);
  EXPECT_EQ(above.normal_peak_hz, at_101.normal_peak_hz);
  EXPECT_EQ(above.tangential_peak_hz, at_101.tangential_peak_hz);
}

TEST(ResonancePeak, AmplitudeBelowOneVoltOrNaNIsOneVolt) {
  ResonancePeak peak(test::li2019_model());
  const ResonanceEstimate one = peak.at(1.0, kReferenceAmbientC);
  for (const double amplitude_v : {0.0, 0.3, 1.4, -50.0, kNaN}) {
    const ResonanceEstimate e = peak.at(amplitude_v, kReferenceAmbientC);
    EXPECT_EQ(e.amplitude_v, 1.0) << amplitude_v;
    EXPECT_EQ(e.normal_peak_hz, one.normal_peak_hz) << amplitude_v;
    EXPECT_EQ(e.tangential_peak_hz, one.tangential_peak_hz) << amplitude_v;
  }
}

TEST(ResonancePeak, Li2019HasNoThermalEffectSoTheTemperatureDoesNotMoveThePeaks) {
  ASSERT_FALSE(test::li2019_model().coefficients().effects.thermal);  // config/li2019.toml: no [effects.thermal]
  ResonancePeak peak(test::li2019_model());
  const ResonanceEstimate room = peak.at(400.0, kReferenceAmbientC);
  for (const double temperature_c : {-40.0, 80.0, 150.0, kNaN}) {
    const ResonanceEstimate e = peak.at(400.0, temperature_c);
    EXPECT_EQ(e.normal_peak_hz, room.normal_peak_hz) << temperature_c;
    EXPECT_EQ(e.tangential_peak_hz, room.tangential_peak_hz) << temperature_c;
  }
}

TEST(ResonancePeak, WithTheThermalEffectTheReferenceTemperatureIsUnshifted) {
  const MotorModel& model = test::thermal_li2019_model();
  ResonancePeak peak(model);
  const BackbonePoint unshifted = FreeStatorHarmonicBalance(model).backbone(400.0);
  const ResonanceEstimate room = peak.at(400.0, kReferenceAmbientC);
  EXPECT_EQ(room.normal_peak_hz, unshifted.normal_peak_hz);
  EXPECT_EQ(room.tangential_peak_hz, unshifted.tangential_peak_hz);
  const ResonanceEstimate unknown = peak.at(400.0, kNaN);  // no temperature: no shift
  EXPECT_EQ(unknown.normal_peak_hz, unshifted.normal_peak_hz);
}

// The linear peak (1 V: no softening) moves by sqrt of the stiffness factor, as a linear
// oscillator's; at 400 V the softening is there too, and it shrinks as the damping grows with
// the temperature (x ~ F / (c w): less amplitude, less softening), so a hot peak moves less
// than sqrt(stiffness) alone would say. The value is the balance with the simulator's factors.
TEST(ResonancePeak, WithTheThermalEffectAHotterStatorMovesItsPeaksByStiffnessAndDamping) {
  const MotorModel& model = test::thermal_li2019_model();
  const EffectCoefficients& e = model.coefficients().effects;
  ASSERT_LT(e.stiffness_per_k, 0.0);  // [effects.thermal]'s defaults: softer and more damped when hot
  ASSERT_GT(e.damping_per_k, 0.0);
  ResonancePeak peak(model);
  const double sqrt_stiffness = std::sqrt(thermal_factors(e, 60.0).stiffness);
  const ResonanceEstimate linear_room = peak.at(1.0, kReferenceAmbientC);
  const ResonanceEstimate linear_hot = peak.at(1.0, kReferenceAmbientC + 60.0);
  EXPECT_NEAR(linear_hot.normal_peak_hz / linear_room.normal_peak_hz, sqrt_stiffness, 1e-4);
  EXPECT_NEAR(linear_hot.tangential_peak_hz / linear_room.tangential_peak_hz, sqrt_stiffness, 1e-4);

  const ResonanceEstimate room = peak.at(400.0, kReferenceAmbientC);
  const ResonanceEstimate hot = peak.at(400.0, kReferenceAmbientC + 60.0);
  // Less softening when hot (at these defaults it outweighs the stiffness: the peak moves up).
  EXPECT_GT(hot.normal_peak_hz, room.normal_peak_hz * sqrt_stiffness + 10.0);
  HarmonicBalanceOptions options;
  options.stiffness_factor = thermal_factors(e, 60.0).stiffness;
  options.damping_factor = thermal_factors(e, 60.0).damping;
  const BackbonePoint expected = FreeStatorHarmonicBalance(model, options).backbone(400.0);
  EXPECT_EQ(hot.normal_peak_hz, expected.normal_peak_hz);
  EXPECT_EQ(hot.tangential_peak_hz, expected.tangential_peak_hz);
  // A cold stator: stiffer, less damped, so softened more than its stiffness alone would say.
  const double sqrt_cold = std::sqrt(thermal_factors(e, -40.0).stiffness);
  EXPECT_LT(peak.at(400.0, kReferenceAmbientC - 40.0).normal_peak_hz, room.normal_peak_hz * sqrt_cold - 10.0);
}

}  // namespace
}  // namespace swum::emu
