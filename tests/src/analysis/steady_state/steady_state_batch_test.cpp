// Batched steady states (analysis/steady_state/steady_state_batch.h) against run_to_steady_state: the same
// values to 1e-6 relative in slip, stick, separation and loaded points, along chains (sweeps)
// too; results independent of the lane count; the scalar fallback gives the scalar result.
#include "analysis/steady_state/steady_state_batch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

#include "../discrepancy_test_support.h"

namespace swum {
namespace {

MotorParameters calibrated() { return test::calibrated_motor(); }

OperatingPoint at(double amplitude_v, double frequency_hz, double load_n = 0.0) {
  OperatingPoint p;
  p.amplitude_v = amplitude_v;
  p.frequency_hz = frequency_hz;
  p.load_n = load_n;
  return p;
}

// Slip, stick (dead zone), separation, loaded.
std::vector<OperatingPoint> regimes() {
  return {at(400.0, 40000.0), at(50.0, 40000.0), at(400.0, 39500.0), at(250.0, 40300.0, 1.0), at(100.0, 40300.0)};
}

// 1e-6 relative, with a floor for values that are zero (a mover at rest in the dead zone).
void expect_close(double batch, double scalar, double floor) {
  EXPECT_NEAR(batch, scalar, 1e-6 * std::max(std::abs(scalar), floor));
}

void expect_agree(const SteadyStateResult& b, const SteadyStateResult& s) {
  EXPECT_EQ(b.ok, s.ok);
  EXPECT_EQ(b.diverged, s.diverged);
  EXPECT_EQ(b.windows, s.windows);
  EXPECT_EQ(b.steps, s.steps);
  EXPECT_EQ(b.sim_s, s.sim_s);
  expect_close(b.speed_mm_s, s.speed_mm_s, 1.0);
  expect_close(b.tip_normal_um, s.tip_normal_um, 0.01);
  expect_close(b.tip_tangential_um, s.tip_tangential_um, 0.01);
  EXPECT_NEAR(b.contact_fraction, s.contact_fraction, 1e-4);
  expect_close(b.damping_power_w, s.damping_power_w, 0.01);
}

void expect_identical(const SteadyStateResult& a, const SteadyStateResult& b) {
  EXPECT_EQ(a.ok, b.ok);
  EXPECT_EQ(a.windows, b.windows);
  EXPECT_EQ(a.speed_mm_s, b.speed_mm_s);
  EXPECT_EQ(a.tip_normal_um, b.tip_normal_um);
  EXPECT_EQ(a.tip_tangential_um, b.tip_tangential_um);
  EXPECT_EQ(a.damping_power_w, b.damping_power_w);
  EXPECT_EQ(a.final_state.q1_m, b.final_state.q1_m);
  EXPECT_EQ(a.final_state.mover_position_m, b.final_state.mover_position_m);
}

TEST(SteadyStateBatch, PointsAgreeWithTheScalarRunInEveryRegime) {
  for (const MotorParameters& p : {calibrated(), MotorParameters{}}) {
    const MotorModel model{p};
    const std::vector<OperatingPoint> points = regimes();
    ASSERT_TRUE(batch_steady_state_supported(model, {}));
    const std::vector<SteadyStateResult> batch = run_points_to_steady_state(model, points);
    ASSERT_EQ(batch.size(), points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      SCOPED_TRACE(testing::Message() << points[i].amplitude_v << " V " << points[i].frequency_hz << " Hz "
                                      << points[i].load_n << " N");
      expect_agree(batch[i], run_to_steady_state(model, points[i]));
    }
  }
}

TEST(SteadyStateBatch, ChainsCarryTheStateLikeAScalarSweep) {
  const MotorModel model{calibrated()};
  // Two downward sweeps through the 400 V peak (hysteresis: a chain differs from points at rest).
  std::vector<OperatingChain> chains(2);
  for (double f = 40600.0; f >= 39300.0; f -= 260.0) chains[0].push_back(at(400.0, f));
  for (double f = 40400.0; f >= 39800.0; f -= 300.0) chains[1].push_back(at(200.0, f, 0.5));
  const SteadyStateOptions options = [] {
    SteadyStateOptions o;  // the discrepancy workflow's measurement protocol
    o.settle_s = 0.040;
    o.window_s = 0.010;
    o.max_s = 0.050;
    return o;
  }();
  std::vector<std::pair<std::size_t, std::size_t>> done;
  const auto batch = run_chains_to_steady_state(model, chains, options, kDefaultBatchLanes,
                                                [&](std::size_t c, std::size_t k, const SteadyStateResult&) {
                                                  done.emplace_back(c, k);
                                                });
  EXPECT_EQ(done.size(), chains[0].size() + chains[1].size());
  for (std::size_t c = 0; c < chains.size(); ++c) {
    std::optional<MotorState> carried;
    for (std::size_t k = 0; k < chains[c].size(); ++k) {
      SCOPED_TRACE(testing::Message() << "chain " << c << " point " << k);
      OperatingPoint p = chains[c][k];
      p.initial_state = carried;
      const SteadyStateResult s = run_to_steady_state(model, p, options);
      expect_agree(batch[c][k], s);
      carried = s.final_state;
    }
  }
}

TEST(SteadyStateBatch, ResultsDoNotDependOnTheLaneCountOrTheOrderOfTheQueue) {
  const MotorModel model{calibrated()};
  std::vector<OperatingPoint> points = regimes();
  for (double f = 39600.0; f <= 40800.0; f += 300.0) points.push_back(at(300.0, f));
  SteadyStateOptions quick;
  quick.settle_s = 0.010;
  quick.window_s = 0.005;
  quick.max_s = 0.040;
  const std::vector<SteadyStateResult> wide = run_points_to_steady_state(model, points, quick, 16);
  const std::vector<SteadyStateResult> narrow = run_points_to_steady_state(model, points, quick, 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    SCOPED_TRACE(i);
    expect_identical(wide[i], narrow[i]);
  }
}

TEST(SteadyStateBatch, WhatTheCallbackThrowsStopsNewPointsAndThoseUnderWayFinish) {
  const MotorModel model{calibrated()};
  std::vector<OperatingChain> chains;
  for (double f = 39600.0; f <= 40800.0; f += 100.0) chains.push_back({at(300.0, f)});
  SteadyStateOptions quick;
  quick.settle_s = 0.010;
  quick.window_s = 0.005;
  std::vector<std::size_t> reported;
  auto throw_first = [&](std::size_t c, std::size_t, const SteadyStateResult& r) {
    EXPECT_GT(r.windows, 0);
    reported.push_back(c);
    if (reported.size() == 1) throw std::runtime_error("stop");
  };
  EXPECT_THROW((void)run_chains_to_steady_state(model, chains, quick, 4, throw_first), std::runtime_error);
  // The point that threw and the three under way in the other lanes; none of the 9 pending.
  ASSERT_EQ(reported.size(), 4U);
  for (std::size_t c : reported) EXPECT_LT(c, 4U);
}

TEST(SteadyStateBatch, ConfigurationsOutsideTheLanesFallBackToTheScalarResult) {
  MotorParameters p;
  p.numerics.friction_solver = FrictionSolver::erf_newton;
  const MotorModel erf{p};
  EXPECT_FALSE(batch_steady_state_supported(erf, {}));
  SteadyStateOptions odd;   // a window that is no whole number of 64-step blocks
  odd.window_s = 0.010004;  // 19208 steps at 48 steps per period
  EXPECT_FALSE(batch_steady_state_supported(MotorModel{calibrated()}, odd));
  const std::vector<OperatingPoint> points = {at(300.0, 40200.0), at(150.0, 40400.0, 0.5)};
  const std::vector<SteadyStateResult> batch = run_points_to_steady_state(erf, points);
  for (std::size_t i = 0; i < points.size(); ++i) expect_identical(batch[i], run_to_steady_state(erf, points[i]));
  // Thermal whose slow state evolves during the run (not frozen): the scalar path, exactly.
  MotorParameters q = calibrated();
  q.effects.thermal.enabled = true;
  q.effects.thermal.thermal_resistance_k_per_w = 5.0;
  const MotorModel thermal{q};
  const std::vector<SteadyStateResult> evolving = run_points_to_steady_state(thermal, points);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SteadyStateResult s = run_to_steady_state(thermal, points[i]);
    expect_identical(evolving[i], s);
    EXPECT_EQ(evolving[i].final_state.stator_temperature_rise_k, s.final_state.stator_temperature_rise_k);
    EXPECT_GT(s.final_state.stator_temperature_rise_k, 0.0);
  }
}

TEST(SteadyStateBatch, DroopPointsRunInLanesAndAgreeWithTheScalarRun) {
  MotorParameters q = calibrated();
  q.effects.amplifier_droop.enabled = true;
  q.effects.amplifier_droop.source_resistance_ohm = 120.0;
  const MotorModel model{q};
  ASSERT_TRUE(batch_steady_state_supported(model, {}));
  const std::vector<OperatingPoint> points = regimes();
  const std::vector<SteadyStateResult> batch = run_points_to_steady_state(model, points);
  for (std::size_t i = 0; i < points.size(); ++i) {
    SCOPED_TRACE(i);
    expect_agree(batch[i], run_to_steady_state(model, points[i]));
  }
}

// Predictions of measured points freeze the slow states: those run in lanes, each lane its own.
TEST(SteadyStateBatch, FrozenThermalAndWearPointsRunInLanesAndAgreeWithTheScalarRun) {
  MotorParameters q = calibrated();
  q.effects.thermal.enabled = true;
  q.effects.thermal.thermal_resistance_k_per_w = 5.0;
  q.effects.wear.enabled = true;
  q.effects.wear.friction_change = 0.3;
  const MotorModel model{q};
  ASSERT_TRUE(batch_steady_state_supported(model, {}));
  std::vector<OperatingPoint> points = regimes();
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i].stator_temperature_rise_k = 8.0 * static_cast<double>(i);
    points[i].sliding_distance_m = 0.7 * static_cast<double>(i);
    points[i].freeze_slow_states = true;
  }
  const std::vector<SteadyStateResult> batch = run_points_to_steady_state(model, points);
  for (std::size_t i = 0; i < points.size(); ++i) {
    SCOPED_TRACE(i);
    const SteadyStateResult s = run_to_steady_state(model, points[i]);
    expect_agree(batch[i], s);
    EXPECT_EQ(batch[i].final_state.stator_temperature_rise_k, s.final_state.stator_temperature_rise_k);
    EXPECT_EQ(batch[i].final_state.sliding_distance_m, s.final_state.sliding_distance_m);
  }
}

}  // namespace
}  // namespace swum
