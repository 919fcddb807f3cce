#include "output/reports/model/simulation_report.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace swum::host {
namespace {

OperatingPoint point() {
  OperatingPoint p;
  p.amplitude_v = 250.0;
  p.frequency_hz = 40000.0;
  p.load_n = 0.5;
  p.phase_deg = 90.0;
  return p;
}

SteadyStateResult result() {
  SteadyStateResult r;
  r.ok = true;
  r.speed_mm_s = 123.4567;
  r.tip_normal_um = 1.23456;
  r.tip_tangential_um = 2.5;
  r.contact_fraction = 0.4567;
  r.mean_normal_force_n = 10.0;
  r.mean_friction_force_n = 1.0;
  r.sim_s = 0.25;
  r.steps = 1000;
  return r;
}

TEST(SimulationText, AlignedLinesAndTheRealTimeFactor) {
  EXPECT_EQ(simulation_text(point(), result(), 0.5), "operating point : 250 V, 40000 Hz, load 0.5 N, phase 90 deg\n"
                                                     "mover speed     : 123.457 mm/s\n"
                                                     "tip amplitudes  : normal 1.2346 um, tangential 2.5000 um\n"
                                                     "contact fraction: 0.457\n"
                                                     "simulated       : 0.2500 s in 0.500 s wall (0.5x real time)\n");
  SteadyStateResult unsettled = result();
  unsettled.ok = false;
  unsettled.failure = "windows disagree";
  EXPECT_NE(simulation_text(point(), unsettled, 0.0)
                .find("phase 90 deg\nnote            : not settled (windows disagree)\nmover speed"),
            std::string::npos);
  EXPECT_NE(simulation_text(point(), unsettled, 0.0).find("(0.0x real time)"), std::string::npos);
}

TEST(SimulationJson, PointValuesAndNoteOnlyWhenNotSettled) {
  const std::string text = simulation_json(point(), result(), 0.5);
  ASSERT_EQ(text.back(), '\n');
  const auto j = nlohmann::json::parse(text);
  EXPECT_DOUBLE_EQ(j["amplitude_v"].get<double>(), 250.0);
  EXPECT_DOUBLE_EQ(j["load_n"].get<double>(), 0.5);
  EXPECT_EQ(j["steady"], true);
  EXPECT_FALSE(j.contains("note"));
  EXPECT_DOUBLE_EQ(j["speed_mm_s"].get<double>(), 123.4567);
  EXPECT_EQ(j["steps"], 1000);
  EXPECT_DOUBLE_EQ(j["realtime_factor"].get<double>(), 0.5);
  SteadyStateResult unsettled = result();
  unsettled.ok = false;
  unsettled.failure = "windows disagree";
  const auto k = nlohmann::json::parse(simulation_json(point(), unsettled, 0.0));
  EXPECT_EQ(k["note"], "windows disagree");
  EXPECT_DOUBLE_EQ(k["realtime_factor"].get<double>(), 0.0);  // no wall time measured
}

TEST(SimulationTrace, HeaderAndRowHaveElevenColumns) {
  EXPECT_EQ(simulation_trace_header(),
            "time_s,q1_m,q1_dot_m_s,q2_m,q2_dot_m_s,tip_normal_um,tip_tangential_um,normal_force_n,"
            "friction_force_n,mover_position_m,mover_velocity_m_s\n");
  TraceSample s{};
  s.time_s = 0.001;
  s.q1_m = 1.5e-6;
  s.tip_normal_um = 1.2345678;
  s.mover_velocity_m_s = 0.1234567891;
  std::string csv = "x\n";
  append_simulation_trace_row(csv, s);
  EXPECT_EQ(csv, "x\n0.001,1.5e-06,0,0,0,1.23457,0,0,0,0,0.123456789\n");
}

}  // namespace
}  // namespace swum::host
