#include "model/simulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace swum {
namespace {

TEST(MotorSimulator, RestsAtPreloadEquilibriumWithoutDrive) {
  const MotorModel model{MotorParameters{}};
  MotorSimulator sim(model);
  sim.advance(100000);
  EXPECT_NEAR(sim.state().q1_m, model.constants().static_q1_m, 1e-15);
  EXPECT_NEAR(sim.state().q2_m, 0.0, 1e-18);
  EXPECT_EQ(sim.state().mover_velocity_m_s, 0.0);
  EXPECT_NEAR(sim.outputs().normal_force_n, 24.8 - 2.58e7 * model.constants().static_q1_m, 1e-9);
  EXPECT_FALSE(sim.diverged());
}

TEST(MotorSimulator, StepAndAdvanceAgree) {
  const MotorModel model{MotorParameters{}};
  MotorSimulator a(model);
  MotorSimulator b(model);
  const DriveInput drive{400.0, 40000.0, 90.0, 0.0};
  a.set_drive(drive);
  b.set_drive(drive);
  a.advance(5000);
  for (int k = 0; k < 5000; ++k) b.step();
  EXPECT_EQ(a.state().q1_m, b.state().q1_m);
  EXPECT_EQ(a.state().mover_position_m, b.state().mover_position_m);
  EXPECT_NEAR(a.state().time_s, 5000 * model.time_step_s(), 1e-15);
}

TEST(MotorSimulator, NanGuardTripsAndResets) {
  const MotorModel model{MotorParameters{}};
  MotorSimulator sim(model);
  sim.set_drive({400.0, 40000.0, 90.0, 0.0});
  sim.advance(1000);
  MotorState bad = sim.state();
  bad.q2_dot_m_s = std::numeric_limits<double>::quiet_NaN();
  sim.set_state(bad);
  sim.step();  // must not throw
  EXPECT_TRUE(sim.diverged());
  EXPECT_EQ(sim.divergence_count(), 1U);
  EXPECT_EQ(sim.state().q1_m, model.constants().static_q1_m);
  EXPECT_EQ(sim.state().q2_m, 0.0);
  EXPECT_TRUE(std::isfinite(sim.state().q2_dot_m_s));
  sim.clear_diverged();
  sim.advance(1000);
  EXPECT_FALSE(sim.diverged());

  MotorState runaway = sim.state();
  runaway.q1_m = 1.0;  // 1 m: far beyond the divergence limit
  sim.set_state(runaway);
  sim.step();
  EXPECT_TRUE(sim.diverged());
  EXPECT_EQ(sim.divergence_count(), 2U);
}

TEST(MotorSimulator, FrequencyChangeKeepsPhaseContinuous) {
  const MotorModel model{MotorParameters{}};
  MotorSimulator sim(model);
  sim.set_drive({300.0, 40000.0, 90.0, 0.0});
  sim.advance(777);
  const auto before = sim.state();
  sim.set_drive({300.0, 39000.0, 90.0, 0.0});
  EXPECT_EQ(sim.state().drive_sin, before.drive_sin);
  EXPECT_EQ(sim.state().drive_cos, before.drive_cos);
}

}  // namespace
}  // namespace swum

namespace swum {
namespace {

TEST(MotorSimulator, AmplitudeOnlyChangeEqualsFreshWaveform) {
  const MotorModel model{MotorParameters{}};
  MotorSimulator a(model);
  MotorSimulator b(model);
  a.set_drive({100.0, 40000.0, 90.0, 0.0});
  a.set_drive({400.0, 40000.0, 90.0, 0.5});  // cheap path
  b.set_drive({400.0, 40000.0, 90.0, 0.5});
  a.advance(3000);
  b.advance(3000);
  EXPECT_EQ(a.state().q1_m, b.state().q1_m);
  EXPECT_EQ(a.state().mover_velocity_m_s, b.state().mover_velocity_m_s);
  EXPECT_EQ(a.voltages().va_v, b.voltages().va_v);
}

}  // namespace
}  // namespace swum
