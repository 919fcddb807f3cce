// BatchSimulator (model/simulation/batch_simulator.h): lanes step like MotorSimulator to rounding, a lane's
// result depends neither on its position nor on the batch size, and the NaN guard resets only
// the lane that diverged.
#include "model/simulation/batch_simulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "calibrated_parameters.h"
#include "model/simulation/simulator.h"

namespace swum {
namespace {

MotorParameters calibrated() { return test::calibrated_parameters(); }

struct Regime {
  const char* name;
  DriveInput drive;
};

// Slip, stick (dead zone), separation, loaded: the regimes of bench_motor_step.
const Regime kRegimes[] = {
    {"slip", {400.0, 40000.0, 90.0, 0.0}},
    {"stick", {50.0, 40000.0, 90.0, 0.0}},
    {"separation", {400.0, 39500.0, 90.0, 0.0}},
    {"loaded", {250.0, 40300.0, 90.0, 1.0}},
};

void expect_same_bits(const MotorState& a, const MotorState& b) {
  EXPECT_EQ(a.q1_m, b.q1_m);
  EXPECT_EQ(a.q2_m, b.q2_m);
  EXPECT_EQ(a.q1_dot_m_s, b.q1_dot_m_s);
  EXPECT_EQ(a.q2_dot_m_s, b.q2_dot_m_s);
  EXPECT_EQ(a.mover_position_m, b.mover_position_m);
  EXPECT_EQ(a.mover_velocity_m_s, b.mover_velocity_m_s);
  EXPECT_EQ(a.contact_deflection_m, b.contact_deflection_m);
  EXPECT_EQ(a.drive_sin, b.drive_sin);
  EXPECT_EQ(a.drive_cos, b.drive_cos);
  EXPECT_EQ(a.time_s, b.time_s);
}

TEST(BatchSimulator, SupportsTheCalibratedAndReferenceModelsAndEffectsButNotTheErfRoot) {
  EXPECT_TRUE(BatchSimulator::supports(MotorModel{calibrated()}));
  EXPECT_TRUE(BatchSimulator::supports(MotorModel{MotorParameters{}}));
  MotorParameters effects = calibrated();
  effects.effects.thermal.enabled = true;  // slow states held fixed per lane
  effects.effects.wear.enabled = true;
  effects.effects.amplifier_droop.enabled = true;
  EXPECT_TRUE(BatchSimulator::supports(MotorModel{effects}));
  MotorParameters erf;
  erf.numerics.friction_solver = FrictionSolver::erf_newton;
  const MotorModel erf_model{erf};
  EXPECT_FALSE(BatchSimulator::supports(erf_model));
  EXPECT_THROW(BatchSimulator(erf_model, 4), std::invalid_argument);
}

// Amplifier droop: each lane's gain follows its motional current every 64 steps.
TEST(BatchSimulator, DroopPerLaneFollowsTheScalarSimulator) {
  MotorParameters p = calibrated();
  p.effects.amplifier_droop.enabled = true;
  p.effects.amplifier_droop.source_resistance_ohm = 120.0;
  const MotorModel model{p};
  BatchSimulator batch(model, std::size(kRegimes));
  for (std::size_t i = 0; i < std::size(kRegimes); ++i) batch.set_lane(i, model.rest_state(), kRegimes[i].drive);
  batch.advance(100);  // not a whole block: the gain updates on the batch clock's blocks
  batch.advance(64 * 400 - 100);
  for (std::size_t i = 0; i < std::size(kRegimes); ++i) {
    SCOPED_TRACE(kRegimes[i].name);
    MotorSimulator sim(model);
    sim.set_drive(kRegimes[i].drive);
    sim.advance(64 * 400);
    EXPECT_NEAR(batch.lane_state(i).q1_m, sim.state().q1_m, 1e-12);
    EXPECT_NEAR(batch.lane_state(i).q2_m, sim.state().q2_m, 1e-12);
    EXPECT_NEAR(batch.lane_state(i).mover_position_m, sim.state().mover_position_m,
                1e-6 * std::abs(sim.state().mover_position_m) + 1e-12);
  }
}

// Thermal and wear: each lane holds its own slow states fixed, as a frozen MotorSimulator does.
TEST(BatchSimulator, FrozenSlowStatesPerLaneFollowTheScalarSimulator) {
  MotorParameters p = calibrated();
  p.effects.thermal.enabled = true;
  p.effects.thermal.thermal_resistance_k_per_w = 5.0;
  p.effects.wear.enabled = true;
  p.effects.wear.friction_change = 0.3;
  const MotorModel model{p};
  const double temperatures[] = {0.0, 12.0, 35.0};
  const double distances[] = {0.0, 0.5, 3.0};
  BatchSimulator batch(model, 3);
  for (std::size_t i = 0; i < 3; ++i) {
    MotorState start = model.rest_state();
    start.stator_temperature_rise_k = temperatures[i];
    start.sliding_distance_m = distances[i];
    batch.set_lane(i, start, kRegimes[0].drive);
  }
  batch.advance(64 * 400);
  for (std::size_t i = 0; i < 3; ++i) {
    SCOPED_TRACE(i);
    MotorSimulator sim(model);
    sim.set_drive(kRegimes[0].drive);
    sim.set_slow_states(temperatures[i], distances[i], true);
    sim.advance(64 * 400);
    const MotorState a = batch.lane_state(i);
    EXPECT_NEAR(a.q1_m, sim.state().q1_m, 1e-12);
    EXPECT_NEAR(a.q2_m, sim.state().q2_m, 1e-12);
    EXPECT_NEAR(a.mover_position_m, sim.state().mover_position_m, 1e-6 * std::abs(sim.state().mover_position_m));
    EXPECT_EQ(a.stator_temperature_rise_k, sim.state().stator_temperature_rise_k);
    EXPECT_EQ(a.sliding_distance_m, sim.state().sliding_distance_m);
  }
  // The lanes differ: the slow states act.
  EXPECT_GT(std::abs(batch.lane_state(2).mover_position_m - batch.lane_state(0).mover_position_m), 1e-7);
}

TEST(BatchSimulator, LanesFollowTheScalarSimulatorInEveryRegime) {
  for (const MotorParameters& p : {calibrated(), MotorParameters{}}) {
    const MotorModel model{p};
    BatchSimulator batch(model, std::size(kRegimes));
    for (std::size_t i = 0; i < std::size(kRegimes); ++i) batch.set_lane(i, model.rest_state(), kRegimes[i].drive);
    constexpr std::uint64_t kSteps = 64 * 400;  // 400 drive periods
    batch.advance(kSteps);
    for (std::size_t i = 0; i < std::size(kRegimes); ++i) {
      SCOPED_TRACE(kRegimes[i].name);
      MotorSimulator sim(model);
      sim.set_drive(kRegimes[i].drive);
      sim.advance(kSteps);
      const MotorState a = batch.lane_state(i);
      const MotorState& b = sim.state();
      // Scales: tip motion ~1e-6 m, modal velocities ~1 m/s, mover ~1e-5 m at these times.
      EXPECT_NEAR(a.q1_m, b.q1_m, 1e-6 * 1e-6);
      EXPECT_NEAR(a.q2_m, b.q2_m, 1e-6 * 1e-6);
      EXPECT_NEAR(a.q1_dot_m_s, b.q1_dot_m_s, 1e-6);
      EXPECT_NEAR(a.q2_dot_m_s, b.q2_dot_m_s, 1e-6);
      EXPECT_NEAR(a.mover_position_m, b.mover_position_m, 1e-6 * std::abs(b.mover_position_m) + 1e-12);
      EXPECT_NEAR(a.mover_velocity_m_s, b.mover_velocity_m_s, 1e-6 * std::abs(b.mover_velocity_m_s) + 1e-9);
      EXPECT_EQ(a.time_s, b.time_s);
      EXPECT_NEAR(batch.lane_forces(i).normal_n, sim.forces().normal_n, 1e-6 * 30.0);
      EXPECT_FALSE(batch.lane_diverged(i));
    }
  }
}

// The default build runs on any x86-64: every target compiled in and available here (SSE2-class
// up to AVX-512) steps the lanes like the scalar simulator.
TEST(BatchSimulator, EveryAvailableSimdTargetFollowsTheScalarSimulator) {
  const MotorModel model{calibrated()};
  const std::vector<std::string> targets = BatchSimulator::available_simd_targets();
  ASSERT_FALSE(targets.empty());
  for (const std::string& target : targets) {
    SCOPED_TRACE(target);
    ASSERT_TRUE(BatchSimulator::restrict_simd_target(target));
    EXPECT_EQ(std::string(BatchSimulator::simd_target()), target);
    BatchSimulator batch(model, std::size(kRegimes));
    for (std::size_t i = 0; i < std::size(kRegimes); ++i) batch.set_lane(i, model.rest_state(), kRegimes[i].drive);
    batch.advance(6400);
    for (std::size_t i = 0; i < std::size(kRegimes); ++i) {
      MotorSimulator sim(model);
      sim.set_drive(kRegimes[i].drive);
      sim.advance(6400);
      EXPECT_NEAR(batch.lane_state(i).q1_m, sim.state().q1_m, 1e-12);
      EXPECT_NEAR(batch.lane_state(i).mover_position_m, sim.state().mover_position_m,
                  1e-6 * std::abs(sim.state().mover_position_m) + 1e-12);
    }
  }
  EXPECT_TRUE(BatchSimulator::restrict_simd_target(""));
  EXPECT_FALSE(BatchSimulator::restrict_simd_target("no such target"));
  EXPECT_EQ(std::string(BatchSimulator::simd_target()), targets.front());
}

TEST(BatchSimulator, ALanesResultDoesNotDependOnItsPositionOrTheBatchSize) {
  const MotorModel model{calibrated()};
  const DriveInput drive = kRegimes[0].drive;
  BatchSimulator alone(model, 1);
  alone.set_lane(0, model.rest_state(), drive);
  alone.advance(6400);
  BatchSimulator many(model, 21);  // three groups of eight, the last padded
  for (std::size_t lane = 0; lane < many.lanes(); ++lane) {
    many.set_lane(lane, model.rest_state(), kRegimes[lane % std::size(kRegimes)].drive);
  }
  many.set_lane(0, model.rest_state(), drive);
  many.set_lane(13, model.rest_state(), drive);
  many.set_lane(20, model.rest_state(), drive);
  many.advance(6400);
  for (std::size_t lane : {0, 13, 20}) {
    SCOPED_TRACE(lane);
    expect_same_bits(many.lane_state(lane), alone.lane_state(0));
  }
}

TEST(BatchSimulator, OneDivergingLaneIsResetAndCountedTheOthersAreUntouched) {
  const MotorModel model{calibrated()};
  const DriveInput drive = kRegimes[0].drive;
  BatchSimulator reference(model, 3);
  BatchSimulator batch(model, 3);
  for (std::size_t lane = 0; lane < 3; ++lane) {
    reference.set_lane(lane, model.rest_state(), drive);
    batch.set_lane(lane, model.rest_state(), drive);
  }
  MotorState runaway = model.rest_state();
  runaway.q2_dot_m_s = std::numeric_limits<double>::quiet_NaN();
  batch.set_lane(1, runaway, drive);
  batch.advance(640);
  reference.advance(640);
  EXPECT_TRUE(batch.lane_diverged(1));
  EXPECT_EQ(batch.lane_divergence_count(1), 1U);
  EXPECT_TRUE(std::isfinite(batch.lane_state(1).q1_m));
  for (std::size_t lane : {0, 2}) {
    EXPECT_FALSE(batch.lane_diverged(lane));
    EXPECT_EQ(batch.lane_divergence_count(lane), 0U);
    expect_same_bits(batch.lane_state(lane), reference.lane_state(lane));
  }
  // The scalar guard does the same to the same state.
  MotorSimulator sim(model);
  sim.set_drive(drive);
  sim.set_state(runaway);
  sim.advance(640);
  EXPECT_EQ(sim.divergence_count(), 1U);
  EXPECT_NEAR(sim.state().q1_m, batch.lane_state(1).q1_m, 1e-12);
}

TEST(BatchSimulator, IdleLanesStayAtRest) {
  const MotorModel model{calibrated()};
  BatchSimulator batch(model, 9);
  batch.set_lane(0, model.rest_state(), kRegimes[0].drive);
  batch.set_idle(0);
  EXPECT_TRUE(batch.idle(0));
  batch.advance(640);
  EXPECT_EQ(batch.lane_state(0).time_s, 0.0);  // a group with no busy lane is not stepped
  batch.set_lane(8, model.rest_state(), kRegimes[0].drive);
  EXPECT_FALSE(batch.idle(8));
  batch.advance(64);
  EXPECT_GT(batch.lane_state(8).time_s, 0.0);
}

// A lane started with its Jenkins deflection outside the cone (a state from another preload or
// mu_c) is projected onto it as the scalar step does (both kernels): the lanes still follow.
TEST(BatchSimulator, DeflectionOutsideTheConeAsTheScalarStep) {
  const MotorModel model{calibrated()};
  MotorSimulator warm(model);
  const DriveInput drive{300.0, 40000.0, 90.0, 0.0};
  warm.set_drive(drive);
  warm.advance(5000);
  for (const double sign : {1.0, -1.0}) {
    MotorState start = warm.state();
    start.contact_deflection_m = sign * 1.2e-7;  // several times the cone at ~20 N
    start.mover_velocity_m_s = sign * 0.3;
    BatchSimulator batch(model, 1);
    batch.set_lane(0, start, drive);
    batch.advance(200);
    MotorSimulator sim(model);
    sim.set_drive(drive);
    sim.set_state(start);
    sim.advance(200);
    EXPECT_NEAR(batch.lane_state(0).mover_position_m, sim.state().mover_position_m, 1e-13);
    EXPECT_NEAR(batch.lane_state(0).mover_velocity_m_s, sim.state().mover_velocity_m_s, 1e-9);
    EXPECT_NEAR(batch.lane_state(0).contact_deflection_m, sim.state().contact_deflection_m, 1e-15);
  }
}

}  // namespace
}  // namespace swum
