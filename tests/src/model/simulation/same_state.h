// Shared by the model tests: two simulators in bit-identical states (state, phasor, time, the
// last step's forces, the droop gain).
#pragma once

#include <gtest/gtest.h>

#include "model/simulation/simulator.h"

namespace swum::test {

inline void expect_same_state(const MotorSimulator& a, const MotorSimulator& b) {
  EXPECT_EQ(a.state().q1_m, b.state().q1_m);
  EXPECT_EQ(a.state().q2_m, b.state().q2_m);
  EXPECT_EQ(a.state().q1_dot_m_s, b.state().q1_dot_m_s);
  EXPECT_EQ(a.state().q2_dot_m_s, b.state().q2_dot_m_s);
  EXPECT_EQ(a.state().mover_position_m, b.state().mover_position_m);
  EXPECT_EQ(a.state().mover_velocity_m_s, b.state().mover_velocity_m_s);
  EXPECT_EQ(a.state().contact_deflection_m, b.state().contact_deflection_m);
  EXPECT_EQ(a.state().drive_sin, b.state().drive_sin);
  EXPECT_EQ(a.state().drive_cos, b.state().drive_cos);
  EXPECT_EQ(a.state().time_s, b.state().time_s);
  EXPECT_EQ(a.forces().normal_n, b.forces().normal_n);
  EXPECT_EQ(a.forces().friction_n, b.forces().friction_n);
  EXPECT_EQ(a.forces().guide_n, b.forces().guide_n);
  EXPECT_EQ(a.droop_gain(), b.droop_gain());
}

}  // namespace swum::test
