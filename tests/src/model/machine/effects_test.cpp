// Time-domain effects in the simulator (model/machine/effects.h, simulator.cpp): disabled effects
// change nothing; the thermal and wear slow states evolve from the motion; droop lowers the
// drive; the static effects change what they claim to.
#include "model/machine/effects.h"

#include <gtest/gtest.h>

#include <cmath>

#include "analysis/steady_state/steady_state.h"
#include "model/simulation/simulator.h"

namespace swum {
namespace {

MotorParameters jenkins_motor() {
  MotorParameters p;
  p.contact.preload_application = PreloadApplication::back_end_constant;
  p.contact.tangential_stiffness_n_m = 2e8;
  p.mover.guide_friction_model = GuideFrictionModel::implicit_coulomb;
  p.stator.substrate_thickness_mm = 2.0;
  return p;
}

MotorState run(const MotorParameters& p, std::uint64_t steps, double* droop = nullptr, double frequency_hz = 40300.0) {
  const MotorModel model(p);
  MotorSimulator sim(model);
  sim.set_drive(DriveInput{250.0, frequency_hz, 90.0, 1.0});
  sim.advance(steps);
  if (droop != nullptr) *droop = sim.droop_gain();
  return sim.state();
}

TEST(Effects, DisabledEffectsLeaveTheSimulationBitwiseUnchanged) {
  MotorParameters p = jenkins_motor();
  const MotorState a = run(p, 20000);
  p.effects.thermal.thermal_resistance_k_per_w = 50.0;  // magnitudes without `enabled`
  p.effects.amplifier_droop.source_resistance_ohm = 500.0;
  p.effects.wear.friction_change = 1.0;
  const MotorState b = run(p, 20000);
  EXPECT_EQ(a.q1_m, b.q1_m);
  EXPECT_EQ(a.q2_dot_m_s, b.q2_dot_m_s);
  EXPECT_EQ(a.mover_velocity_m_s, b.mover_velocity_m_s);
  EXPECT_EQ(b.stator_temperature_rise_k, 0.0);
}

class ThermalSteadyState : public ::testing::TestWithParam<double> {};

// At 40 kHz the simulator's 64-step housekeeping block is exactly one drive period: a heating
// power sampled once per block would always see the same phase of C v^2 (-57 %..+58 % of the
// mean). The cycle-mean estimate must hold there as well as off it.
TEST_P(ThermalSteadyState, HeatsTowardsRthTimesTheMeanDampingPower) {
  const double frequency_hz = GetParam();
  MotorParameters p = jenkins_motor();
  p.effects.thermal.enabled = true;
  p.effects.thermal.thermal_resistance_k_per_w = 5.0;
  p.effects.thermal.time_constant_s = 0.01;                    // short, so the test sees it settle
  const MotorState s = run(p, 200000, nullptr, frequency_hz);  // 78 ms
  EXPECT_GT(s.stator_temperature_rise_k, 1.0);
  // Steady state: T = R_th P with P the time-averaged damping power at that temperature.
  const MotorModel model(p);
  OperatingPoint point{250.0, frequency_hz, 1.0, 90.0, s.stator_temperature_rise_k, 0.0, true};
  const SteadyStateResult r = run_to_steady_state(model, point);
  EXPECT_NEAR(s.stator_temperature_rise_k, 5.0 * r.damping_power_w, 0.05 * s.stator_temperature_rise_k);
}

INSTANTIATE_TEST_SUITE_P(DriveFrequencies, ThermalSteadyState, ::testing::Values(40000.0, 40300.0));

TEST(Effects, SlowStatesEvolveInAFreeSteadyStateRunAndHoldWhenFrozen) {
  MotorParameters p = jenkins_motor();
  p.effects.thermal.enabled = true;
  p.effects.thermal.thermal_resistance_k_per_w = 8.0;
  p.effects.thermal.time_constant_s = 0.005;
  const MotorModel hot(p);
  const MotorModel cold(jenkins_motor());
  OperatingPoint point{250.0, 40300.0, 1.0, 90.0, 0.0, 0.0, false};
  const SteadyStateResult evolving = run_to_steady_state(hot, point);  // what `swum simulate` runs
  point.freeze_slow_states = true;
  const SteadyStateResult frozen = run_to_steady_state(hot, point);
  const SteadyStateResult baseline = run_to_steady_state(cold, point);
  EXPECT_EQ(frozen.speed_mm_s, baseline.speed_mm_s) << "frozen at 0 K = no effect";
  EXPECT_GT(std::abs(evolving.tip_normal_um - baseline.tip_normal_um), 0.05 * baseline.tip_normal_um)
      << "a heated stator must vibrate differently";
}

TEST(Effects, WearAccumulatesTheMoverTravelAndDroopLowersTheDrive) {
  MotorParameters p = jenkins_motor();
  p.effects.wear.enabled = true;
  p.effects.amplifier_droop.enabled = true;
  double droop = 1.0;
  const MotorState s = run(p, 100000, &droop);
  EXPECT_NEAR(s.sliding_distance_m, std::abs(s.mover_position_m), 0.05 * std::abs(s.mover_position_m) + 1e-9);
  EXPECT_GT(s.sliding_distance_m, 0.0);
  EXPECT_LT(droop, 1.0);
  EXPECT_GT(droop, 0.5);
  EXPECT_LT(wear_friction_factor(make_effect_coefficients(p, ModalConstants{}), 1e6),
            1.0 + p.effects.wear.friction_change + 1e-12);
}

// One C0: the droop's divider 1/|1 + j w R_s C0| takes C0 from the stator (the electrical
// port's clamped capacitance), so changing it there changes the droop.
TEST(Effects, DroopUsesTheStatorsClampedCapacitance) {
  MotorParameters p = jenkins_motor();
  p.effects.amplifier_droop.enabled = true;
  p.effects.amplifier_droop.source_resistance_ohm = 500.0;
  const double w = 2.0 * 3.141592653589793 * 40000.0;
  for (const double c0_nf : {10.0, 40.0}) {
    p.stator.clamped_capacitance_nf = c0_nf;
    const EffectCoefficients e = make_effect_coefficients(p, ModalConstants{});
    EXPECT_EQ(e.clamped_capacitance_f, c0_nf * 1e-9);
    const double x = w * 500.0 * c0_nf * 1e-9;
    EXPECT_DOUBLE_EQ(droop_gain(e, w, 0.0, 1.0, 0.0, 1.0, 0.0, {}, {}), 1.0 / std::sqrt(1.0 + x * x));
  }
}

TEST(Effects, StaticEffectsFoldIntoTheParameters) {
  MotorParameters p = linearised(jenkins_motor());
  p.effects.electroelastic.enabled = true;
  p.effects.electroelastic.scale = 0.5;
  p.effects.preload.enabled = true;
  p.effects.preload.preload_factor = 0.8;
  p.effects.guide_friction.enabled = true;
  p.effects.guide_friction.extra_coefficient = 0.01;
  const MotorParameters e = with_static_effects(p);
  EXPECT_DOUBLE_EQ(e.stator.c1111_pa, 0.5 * ReferenceNonlinearConstants{}.c1111_pa);
  EXPECT_DOUBLE_EQ(e.stator.e3111_c_per_v_m, 0.5 * ReferenceNonlinearConstants{}.e3111_c_per_v_m);
  EXPECT_DOUBLE_EQ(e.contact.preload_n, 0.8 * p.contact.preload_n);
  EXPECT_DOUBLE_EQ(e.contact.stiffness_n_m, std::cbrt(0.8) * p.contact.stiffness_n_m);
  EXPECT_DOUBLE_EQ(e.mover.guide_friction_coefficient, p.mover.guide_friction_coefficient + 0.01);
}

}  // namespace
}  // namespace swum
