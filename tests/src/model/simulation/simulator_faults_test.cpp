// Run-time faults of MotorSimulator (model_faults.h) on the calibrated motor
// (config/li2019.toml) at 400 V, 40 kHz: physical effect of each hook, the jam, recovery
// after clearing, and bit-identity of the nominal dynamics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "calibrated_parameters.h"
#include "model/simulation/model_faults.h"
#include "model/simulation/simulator.h"
#include "same_state.h"

namespace swum {
namespace {

MotorParameters calibrated() { return test::calibrated_parameters(); }

constexpr DriveInput kDrive{400.0, 40000.0, 90.0, 0.0};

std::uint64_t steps_for(const MotorSimulator& sim, double duration_s) {
  return static_cast<std::uint64_t>(std::llround(duration_s / sim.time_step_s()));
}

// What a window of steps shows: mean mover speed, half peak-to-peak tip motions, mean F_N.
struct Window {
  double speed_m_s = 0.0;
  double tip_normal_um = 0.0;
  double tip_tangential_um = 0.0;
  double normal_force_n = 0.0;
  double friction_abs_n = 0.0;  // mean |F_T|
};

Window measure(MotorSimulator& sim, double duration_s) {
  const std::uint64_t steps = steps_for(sim, duration_s);
  const double x0 = sim.state().mover_position_m;
  const double t0 = sim.state().time_s;
  double u_min = 1e300, u_max = -1e300, w_min = 1e300, w_max = -1e300;
  Window w;
  for (std::uint64_t k = 0; k < steps; ++k) {
    sim.step();
    const MotorOutputs o = sim.outputs();
    u_min = std::min(u_min, o.tip_normal_um);
    u_max = std::max(u_max, o.tip_normal_um);
    w_min = std::min(w_min, o.tip_tangential_um);
    w_max = std::max(w_max, o.tip_tangential_um);
    w.normal_force_n += o.normal_force_n;
    w.friction_abs_n += std::abs(o.friction_force_n);
  }
  w.speed_m_s = (sim.state().mover_position_m - x0) / (sim.state().time_s - t0);
  w.tip_normal_um = 0.5 * (u_max - u_min);
  w.tip_tangential_um = 0.5 * (w_max - w_min);
  w.normal_force_n /= static_cast<double>(steps);
  w.friction_abs_n /= static_cast<double>(steps);
  return w;
}

// 20 ms to reach the periodic regime (the modes settle in ~1 ms, the 0.2 kg mover in a few),
// then a 10 ms window.
constexpr double kSettleS = 20e-3;
constexpr double kWindowS = 10e-3;

Window steady(const MotorModel& model, const ModelFaults& faults, const DriveInput& drive = kDrive,
              double settle_s = kSettleS) {
  MotorSimulator sim(model);
  sim.set_drive(drive);
  sim.set_faults(faults);
  sim.advance(steps_for(sim, settle_s));
  return measure(sim, kWindowS);
}

// Nominal faults, set before and during a run (and after a fault was cleared), leave the
// trajectory bit-identical to a simulator that never saw set_faults, with and without the
// amplifier droop (the one effect that reads the phase amplitudes in the housekeeping).
TEST(MotorSimulatorFaults, NominalFaultsAreBitIdentical) {
  for (const bool droop : {false, true}) {
    SCOPED_TRACE(droop ? "droop" : "no droop");
    MotorParameters p = calibrated();
    p.effects.amplifier_droop.enabled = droop;
    const MotorModel model(p);
    MotorSimulator plain(model);
    MotorSimulator hooked(model);
    EXPECT_TRUE(hooked.faults().nominal());
    plain.set_drive(kDrive);
    hooked.set_faults(ModelFaults{});
    hooked.set_drive(kDrive);
    plain.advance(20000);
    hooked.advance(20000);
    test::expect_same_state(plain, hooked);
    // A fault set and cleared before any step: nothing of it remains.
    hooked.set_faults({.phase_a_gain = 0.3, .preload_factor = 0.5, .guide_friction_factor = 4.0, .jammed = false});
    hooked.set_faults(ModelFaults{});
    // Amplitude-only set_drive (the fast path) with the faults in place.
    plain.set_drive({300.0, 40000.0, 90.0, 0.1});
    hooked.set_drive({300.0, 40000.0, 90.0, 0.1});
    WindowStatistics wa, wb;
    plain.advance(10001, wa);
    hooked.advance(10001, wb);
    test::expect_same_state(plain, hooked);
    EXPECT_EQ(wa.energy_j, wb.energy_j);
    EXPECT_EQ(wa.fn_sum_n_s, wb.fn_sum_n_s);
    EXPECT_EQ(plain.voltages().va_v, hooked.voltages().va_v);
    EXPECT_EQ(plain.voltages().vb_v, hooked.voltages().vb_v);
    EXPECT_EQ(plain.divergence_count(), 0U);
  }
}

// Both phases at gain g are the drive at g V0: with g = 0.5 (exact in binary) the trajectory is
// bit-identical to a 200 V drive, through set_drive's fast path too.
TEST(MotorSimulatorFaults, EqualPhaseGainsAreALowerVoltage) {
  const MotorModel model(calibrated());
  MotorSimulator sagged(model);
  MotorSimulator lower(model);
  sagged.set_drive(kDrive);
  sagged.set_faults({.phase_a_gain = 0.5, .phase_b_gain = 0.5});
  lower.set_drive({200.0, 40000.0, 90.0, 0.0});
  sagged.advance(15000);
  lower.advance(15000);
  test::expect_same_state(sagged, lower);
  sagged.set_drive({300.0, 40000.0, 90.0, 0.0});  // amplitude only: the gains stay applied
  lower.set_drive({150.0, 40000.0, 90.0, 0.0});
  sagged.advance(15000);
  lower.advance(15000);
  test::expect_same_state(sagged, lower);
  EXPECT_EQ(sagged.voltages().va_v, lower.voltages().va_v);
  EXPECT_EQ(sagged.voltages().vb_v, lower.voltages().vb_v);
}

TEST(MotorSimulatorFaults, PhaseGainsScaleEachPhaseVoltage) {
  const MotorModel model(calibrated());
  MotorSimulator sim(model);
  sim.set_drive(kDrive);
  sim.advance(37);  // a phase where both voltages are non-zero
  const DriveVoltages nominal = sim.voltages();
  ASSERT_NE(nominal.va_v, 0.0);
  ASSERT_NE(nominal.vb_v, 0.0);
  sim.set_faults({.phase_b_gain = 0.0});
  EXPECT_EQ(sim.voltages().va_v, nominal.va_v);
  EXPECT_EQ(sim.voltages().vb_v, 0.0);
  sim.set_faults({.phase_a_gain = 0.25, .phase_b_gain = 1.5});
  EXPECT_EQ(sim.voltages().va_v, 0.25 * nominal.va_v);
  EXPECT_DOUBLE_EQ(sim.voltages().vb_v, 1.5 * nominal.vb_v);
}

// The elliptical tip motion needs both phases (model_spec §4): each phase forces L1 and B2
// (a0 = 0.107 N/V from A and B alike, b0 = -0.125 N/V from A, +0.125 N/V from B), and at
// +90 deg the two phases drive the modes in quadrature. One phase alone drives the modes in
// (anti)phase; only the different resonance lags of L1 and B2 at 40 kHz open the ellipse a
// little. Measured (li2019, 400 V, 40 kHz, 40 ms to settle, the 0.2 kg mover takes ~40 ms):
// 610 mm/s nominal, 149 mm/s with phase B open (0.24), -149 mm/s with phase A open (the
// electrode pattern mirrors the bending forcing, so the motor runs backwards at the same speed).
TEST(MotorSimulatorFaults, OnePhaseOpenCollapsesTheSpeed) {
  const MotorModel model(calibrated());
  const Window nominal = steady(model, {}, kDrive, 40e-3);
  const Window open_b = steady(model, {.phase_b_gain = 0.0}, kDrive, 40e-3);
  const Window open_a = steady(model, {.phase_a_gain = 0.0}, kDrive, 40e-3);
  RecordProperty("nominal_speed_mm_s", std::to_string(1e3 * nominal.speed_m_s));
  RecordProperty("phase_b_open_speed_mm_s", std::to_string(1e3 * open_b.speed_m_s));
  RecordProperty("phase_a_open_speed_mm_s", std::to_string(1e3 * open_a.speed_m_s));
  ASSERT_GT(nominal.speed_m_s, 0.5);  // the calibrated motor at 400 V
  EXPECT_LT(std::abs(open_b.speed_m_s), 0.35 * nominal.speed_m_s);
  EXPECT_GT(open_b.tip_tangential_um, 0.0);  // the stator still vibrates
  EXPECT_NEAR(open_a.speed_m_s, -open_b.speed_m_s, 0.02 * std::abs(open_b.speed_m_s));
  // Both open: no drive at all.
  const Window open = steady(model, {.phase_a_gain = 0.0, .phase_b_gain = 0.0});
  EXPECT_EQ(open.speed_m_s, 0.0);
  EXPECT_EQ(open.tip_tangential_um, 0.0);
}

TEST(MotorSimulatorFaults, SagLowersSpeedAndHalvesTheTipMotion) {
  const MotorModel model(calibrated());
  const Window nominal = steady(model, {});
  const Window sag = steady(model, {.phase_a_gain = 0.5, .phase_b_gain = 0.5});
  RecordProperty("sag_speed_mm_s", std::to_string(1e3 * sag.speed_m_s));
  RecordProperty("sag_tip_normal_ratio", std::to_string(sag.tip_normal_um / nominal.tip_normal_um));
  RecordProperty("sag_tip_tangential_ratio", std::to_string(sag.tip_tangential_um / nominal.tip_tangential_um));
  // Measured: 300 mm/s against 598 mm/s (0.50); tip ratios 0.68 (normal) and 0.59
  // (tangential). Half the forcing gives half the free vibration, but the contact clips the
  // inward normal stroke and damps the bending mode by friction, more so at full drive.
  EXPECT_LT(sag.speed_m_s, 0.6 * nominal.speed_m_s);
  EXPECT_GT(sag.tip_normal_um / nominal.tip_normal_um, 0.45);
  EXPECT_LT(sag.tip_normal_um / nominal.tip_normal_um, 0.75);
  EXPECT_GT(sag.tip_tangential_um / nominal.tip_tangential_um, 0.45);
  EXPECT_LT(sag.tip_tangential_um / nominal.tip_tangential_um, 0.75);
}

TEST(MotorSimulatorFaults, PreloadLossLowersTheNormalForce) {
  const MotorModel model(calibrated());
  const Window nominal = steady(model, {});
  const Window loss = steady(model, {.preload_factor = 0.5});
  RecordProperty("nominal_mean_normal_force_n", std::to_string(nominal.normal_force_n));
  RecordProperty("half_preload_mean_normal_force_n", std::to_string(loss.normal_force_n));
  // Measured: mean F_N 41.3 N against 48.9 N (0.84). At 400 V the tip strokes 4.5 um
  // against a static preload compression of 0.08 um, so the impacts, not F_P, carry most of
  // the mean normal force.
  EXPECT_LT(loss.normal_force_n, 0.9 * nominal.normal_force_n);
  EXPECT_GT(loss.normal_force_n, 0.7 * nominal.normal_force_n);
  // At rest F_N is F_P - k_e q1 at the static equilibrium, linear in F_P (the cubic terms are
  // ~1e-6): half the preload, half the force. rest_state is not moved; the stator settles from
  // it to the new equilibrium.
  MotorSimulator rest(model);
  const double nominal_rest_n = 24.8 - 2.58e7 * model.constants().static_q1_m;
  rest.set_faults({.preload_factor = 0.5});
  EXPECT_EQ(rest.state().q1_m, model.rest_state().q1_m);
  rest.advance(steps_for(rest, 30e-3));
  EXPECT_NEAR(rest.state().q1_m, 0.5 * model.constants().static_q1_m, 1e-5 * model.constants().static_q1_m);
  EXPECT_NEAR(rest.outputs().normal_force_n, 0.5 * nominal_rest_n, 1e-5 * nominal_rest_n);
}

// The factors act exactly like a motor built with the scaled parameter (powers of two keep the
// products exact): from the same state the trajectories are bit-identical.
TEST(MotorSimulatorFaults, FactorsEqualAMotorWithScaledParameters) {
  const MotorParameters base = calibrated();
  const MotorModel model(base);
  MotorParameters half_preload = base;
  half_preload.contact.preload_n *= 0.5;
  MotorParameters double_guide = base;
  double_guide.mover.guide_friction_coefficient *= 2.0;
  const DriveInput loaded{400.0, 40000.0, 90.0, 0.5};
  for (const auto& [parameters, faults] : {std::pair{half_preload, ModelFaults{.preload_factor = 0.5}},
                                           std::pair{double_guide, ModelFaults{.guide_friction_factor = 2.0}}}) {
    const MotorModel scaled_model(parameters);
    MotorSimulator faulted(model);
    MotorSimulator scaled(scaled_model);
    faulted.set_faults(faults);
    scaled.set_state(model.rest_state());
    faulted.set_drive(loaded);
    scaled.set_drive(loaded);
    faulted.advance(steps_for(faulted, 5e-3));
    scaled.advance(steps_for(scaled, 5e-3));
    test::expect_same_state(faulted, scaled);
    EXPECT_NE(faulted.state().mover_position_m, 0.0);
  }
}

TEST(MotorSimulatorFaults, GuideFrictionRaisesTheLoss) {
  const MotorModel model(calibrated());
  const DriveInput loaded{400.0, 40000.0, 90.0, 0.5};
  const Window nominal = steady(model, {}, loaded);
  const Window sticky = steady(model, {.guide_friction_factor = 3.0}, loaded);
  RecordProperty("loaded_speed_mm_s", std::to_string(1e3 * nominal.speed_m_s));
  RecordProperty("guide_x3_speed_mm_s", std::to_string(1e3 * sticky.speed_m_s));
  ASSERT_GT(nominal.speed_m_s, 0.0);
  // Measured: 452 mm/s against 583 mm/s (0.77): the guide's Coulomb force
  // mu_s (F_N + m g) goes from 2.0 N to 6.1 N against a contact drive of a few N.
  EXPECT_LT(sticky.speed_m_s, 0.9 * nominal.speed_m_s);
}

// A jam holds the mover exactly (v_m = 0, x_m = the jam position, bit for bit) while the stator
// still vibrates and rubs on it.
TEST(MotorSimulatorFaults, JamHoldsTheMoverWhileTheStatorVibrates) {
  const MotorModel model(calibrated());
  const Window nominal = steady(model, {});
  MotorSimulator sim(model);
  sim.set_drive(kDrive);
  sim.advance(steps_for(sim, kSettleS));
  ASSERT_GT(sim.state().mover_velocity_m_s, 0.0);
  const double where = sim.state().mover_position_m;
  sim.set_faults({.jammed = true, .jam_position_m = std::numeric_limits<double>::quiet_NaN()});
  EXPECT_EQ(sim.faults().jam_position_m, where);   // NaN: the current position
  EXPECT_EQ(sim.state().mover_velocity_m_s, 0.0);  // at once
  const Window jammed = measure(sim, kWindowS);
  EXPECT_EQ(sim.state().mover_position_m, where);
  EXPECT_EQ(sim.state().mover_velocity_m_s, 0.0);
  EXPECT_EQ(jammed.speed_m_s, 0.0);
  EXPECT_EQ(sim.forces().guide_n, 0.0);
  // Measured: tangential tip amplitude 0.98 of the running motor, mean |F_T| 17 N.
  RecordProperty("jammed_tip_tangential_ratio", std::to_string(jammed.tip_tangential_um / nominal.tip_tangential_um));
  RecordProperty("jammed_mean_abs_friction_n", std::to_string(jammed.friction_abs_n));
  EXPECT_GT(jammed.tip_normal_um, 0.3 * nominal.tip_normal_um);
  EXPECT_GT(jammed.tip_tangential_um, 0.1 * nominal.tip_tangential_um);
  EXPECT_GT(jammed.friction_abs_n, 0.5);  // the tip rubs on the stationary mover
  // An explicit position, with the windowed advance and through reset().
  sim.set_faults({.jammed = true, .jam_position_m = 1e-3});
  WindowStatistics window;
  sim.advance(5000, window);
  EXPECT_EQ(sim.state().mover_position_m, 1e-3);
  EXPECT_EQ(sim.state().mover_velocity_m_s, 0.0);
  sim.reset();
  EXPECT_EQ(sim.state().mover_position_m, 1e-3);
  sim.advance(5000);
  EXPECT_EQ(sim.state().mover_position_m, 1e-3);
  EXPECT_EQ(sim.state().mover_velocity_m_s, 0.0);
}

// The held mover with the other contact laws and guide model (the paper's reference set:
// Coulomb projection or erf root, smoothed-sign guide).
TEST(MotorSimulatorFaults, JamHoldsTheMoverWithEveryContactLaw) {
  for (const FrictionSolver solver : {FrictionSolver::coulomb_projection, FrictionSolver::erf_newton}) {
    MotorParameters p{};
    p.numerics.friction_solver = solver;
    const MotorModel model(p);
    MotorSimulator sim(model);
    sim.set_drive({400.0, 40000.0, 90.0, 0.2});
    sim.advance(20000);
    const double where = sim.state().mover_position_m;
    ASSERT_NE(where, 0.0);
    sim.set_faults({.jammed = true, .jam_position_m = std::numeric_limits<double>::quiet_NaN()});
    const Window jammed = measure(sim, 5e-3);
    EXPECT_EQ(sim.state().mover_position_m, where);
    EXPECT_EQ(sim.state().mover_velocity_m_s, 0.0);
    EXPECT_GT(jammed.tip_tangential_um, 0.1);
    EXPECT_GT(jammed.friction_abs_n, 0.1);
    EXPECT_FALSE(sim.diverged());
  }
}

TEST(MotorSimulatorFaults, ClearingRecoversTheNominalSpeed) {
  const MotorModel model(calibrated());
  const Window nominal = steady(model, {});
  MotorSimulator sim(model);
  sim.set_drive(kDrive);
  sim.set_faults({.phase_b_gain = 0.0,
                  .preload_factor = 0.5,
                  .guide_friction_factor = 3.0,
                  .jammed = true,
                  .jam_position_m = std::numeric_limits<double>::quiet_NaN()});
  sim.advance(steps_for(sim, 10e-3));
  EXPECT_EQ(sim.state().mover_position_m, 0.0);
  sim.set_faults(ModelFaults{});
  EXPECT_TRUE(sim.faults().nominal());
  sim.advance(steps_for(sim, kSettleS));
  const Window recovered = measure(sim, kWindowS);
  // Measured: 599.0 mm/s against 598.5 mm/s (both 20 ms after starting from rest).
  RecordProperty("recovered_speed_mm_s", std::to_string(1e3 * recovered.speed_m_s));
  EXPECT_NEAR(recovered.speed_m_s, nominal.speed_m_s, 0.05 * nominal.speed_m_s);
}

TEST(MotorSimulatorFaults, OutOfRangeValuesThrowNamingTheField) {
  const MotorModel model(calibrated());
  MotorSimulator sim(model);
  sim.set_faults({.preload_factor = 0.7});
  auto expect_rejected = [&sim](const ModelFaults& bad, const std::string& field) {
    EXPECT_NE(check(bad).find(field), std::string::npos) << check(bad);
    try {
      sim.set_faults(bad);
      ADD_FAILURE() << "accepted " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
    EXPECT_EQ(sim.faults().preload_factor, 0.7);  // the faults in force are unchanged
  };
  constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  expect_rejected({.phase_a_gain = -0.1}, "phase_a_gain");
  expect_rejected({.phase_a_gain = kNan}, "phase_a_gain");
  expect_rejected({.phase_b_gain = 2.5}, "phase_b_gain");
  expect_rejected({.preload_factor = 1.01}, "preload_factor");
  expect_rejected({.preload_factor = -1.0}, "preload_factor");
  expect_rejected({.guide_friction_factor = 10.5}, "guide_friction_factor");
  expect_rejected({.guide_friction_factor = -0.5}, "guide_friction_factor");
  expect_rejected({.jammed = true, .jam_position_m = std::numeric_limits<double>::infinity()}, "jam_position_m");
  EXPECT_EQ(check(ModelFaults{}), "");
  EXPECT_EQ(check({.phase_a_gain = 0.0,
                   .phase_b_gain = 2.0,
                   .preload_factor = 0.0,
                   .guide_friction_factor = 10.0,
                   .jammed = true,
                   .jam_position_m = kNan}),
            "");
  EXPECT_FALSE(ModelFaults{.guide_friction_factor = 2.0}.nominal());
  EXPECT_FALSE(ModelFaults{.jammed = true}.nominal());
  EXPECT_TRUE(ModelFaults{.jam_position_m = 5.0}.nominal());  // ignored when not jammed
}

}  // namespace
}  // namespace swum
