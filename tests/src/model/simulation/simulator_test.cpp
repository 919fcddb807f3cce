#include "model/simulation/simulator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "calibrated_parameters.h"
#include "integrators/semi_implicit_euler.h"
#include "same_state.h"

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

// advance(steps, window) is the step()-by-step loop that reads state() and forces() after each
// step, fused into the hot loop: the same trajectory and bit-identical sums, for every contact
// law and guide model (dispatch) and through a divergence reset.
std::uint64_t expect_windowed_advance_equals_steps(const MotorParameters& parameters, const DriveInput& drive) {
  const MotorModel model{parameters};
  MotorSimulator fused(model);
  MotorSimulator stepped(model);
  fused.set_drive(drive);
  stepped.set_drive(drive);
  WindowStatistics a, b;
  a.c1_n_s_m = b.c1_n_s_m = model.coefficients().c1_n_s_m;
  a.c2_n_s_m = b.c2_n_s_m = 0.5 * model.coefficients().c2_n_s_m;
  constexpr int kSteps = 3001;  // not a multiple of the 64-step housekeeping block
  fused.advance(kSteps, a);
  for (int k = 0; k < kSteps; ++k) {
    stepped.step();
    const MotorState& s = stepped.state();
    const InterfaceForces& f = stepped.forces();
    b.add(model.time_step_s(), -s.q1_m, model.coefficients().g_tv * s.q2_m, f.normal_n, f.friction_n,
          b.damping_power_w(s.q1_dot_m_s, s.q2_dot_m_s));
  }
  EXPECT_EQ(fused.state().q1_m, stepped.state().q1_m);
  EXPECT_EQ(fused.state().q2_dot_m_s, stepped.state().q2_dot_m_s);
  EXPECT_EQ(fused.state().mover_position_m, stepped.state().mover_position_m);
  EXPECT_EQ(fused.state().time_s, stepped.state().time_s);
  EXPECT_EQ(a.duration_s, b.duration_s);
  EXPECT_EQ(a.u_min_m, b.u_min_m);
  EXPECT_EQ(a.u_max_m, b.u_max_m);
  EXPECT_EQ(a.w_min_m, b.w_min_m);
  EXPECT_EQ(a.w_max_m, b.w_max_m);
  EXPECT_EQ(a.contact_s, b.contact_s);
  EXPECT_EQ(a.ft_sum_n_s, b.ft_sum_n_s);
  EXPECT_EQ(a.ft2_sum_n2_s, b.ft2_sum_n2_s);
  EXPECT_EQ(a.fn_sum_n_s, b.fn_sum_n_s);
  EXPECT_EQ(a.energy_j, b.energy_j);
  EXPECT_GT(a.energy_j, 0.0);
  EXPECT_GT(a.u_max_m, a.u_min_m);
  EXPECT_EQ(fused.divergence_count(), stepped.divergence_count());
  return fused.divergence_count();
}

TEST(MotorSimulator, WindowedAdvanceEqualsStepsReadOneByOne) {
  MotorParameters rigid_erf{};
  rigid_erf.numerics.friction_solver = FrictionSolver::erf_newton;
  MotorParameters jenkins{};
  jenkins.contact.tangential_stiffness_n_m = 2e8;
  jenkins.mover.guide_friction_model = GuideFrictionModel::implicit_coulomb;
  for (const MotorParameters& p : {MotorParameters{}, rigid_erf, jenkins}) {
    expect_windowed_advance_equals_steps(p, {400.0, 40000.0, 90.0, 0.0});
    expect_windowed_advance_equals_steps(p, {400.0, 39500.0, 90.0, 0.5});
  }
}

TEST(MotorSimulator, WindowedAdvanceThroughDivergenceResets) {
  MotorParameters p{};
  p.numerics.divergence_speed_limit_m_s = 0.005;  // the 400 V mover passes 5 mm/s early: reset to rest, again
  EXPECT_GT(expect_windowed_advance_equals_steps(p, {400.0, 40000.0, 90.0, 0.0}), 0U);
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

namespace swum {
namespace {

MotorParameters calibrated_terms() {
  MotorParameters p{};
  p.stator.substrate_thickness_mm = 2.0;
  p.stator.c1111_pa = -0.85e17;
  p.contact.preload_application = PreloadApplication::back_end_constant;
  p.contact.tangential_stiffness_n_m = 2e8;
  p.mover.guide_friction_model = GuideFrictionModel::implicit_coulomb;
  return p;
}

TEST(BackEndPreload, StaticEquilibriumIsTheRestState) {
  MotorParameters p{};
  p.contact.preload_application = PreloadApplication::back_end_constant;
  const MotorModel model(p);
  const auto& c = model.constants();
  EXPECT_DOUBLE_EQ(c.g_n, 1.0);
  EXPECT_DOUBLE_EQ(c.g_np, 1.0);
  // Linear estimate 2 F_P/(K1 + k_e) (cubic terms change it by < 1e-6).
  EXPECT_NEAR(c.static_q1_m, 2.0 * 24.8 / (c.k1_n_m + 2.58e7), 1e-5 * c.static_q1_m);
  MotorSimulator sim(model);
  sim.advance(100000);
  EXPECT_NEAR(sim.state().q1_m, c.static_q1_m, 1e-15);
  EXPECT_NEAR(sim.outputs().normal_force_n, 24.8 - 2.58e7 * c.static_q1_m, 1e-9);
  // both_ends: gN = 2, no constant term.
  const MotorModel literal{MotorParameters{}};
  EXPECT_DOUBLE_EQ(literal.constants().g_n, 2.0);
  EXPECT_EQ(literal.constants().g_np, 0.0);
}

TEST(JenkinsContact, SticksElasticallyAtLowDriveAndStaysInTheCone) {
  const MotorModel model(calibrated_terms());
  MotorSimulator sim(model);
  sim.set_drive({40.0, 40000.0, 90.0, 0.0});  // dead zone: contact sticks, mover at rest
  sim.advance(60000);
  const double kt = 2e8;
  bool elastic_stick = false;
  for (int k = 0; k < 2000; ++k) {
    sim.step();
    const auto& f = sim.forces();
    const double delta = sim.state().contact_deflection_m;
    EXPECT_LE(std::abs(kt * delta), 0.35 * std::max(0.0, 24.8 - 2.58e7 * sim.state().q1_m) + 1e-9);
    if (std::abs(f.friction_n) > 0.05 && std::abs(f.friction_n) < 0.9 * 0.35 * f.normal_n) {
      elastic_stick = true;
    }
  }
  EXPECT_TRUE(elastic_stick);
  EXPECT_LT(std::abs(sim.state().mover_velocity_m_s), 1e-3);
}

TEST(JenkinsContact, SlidesAtTheLimitAndResetsInSeparation) {
  const MotorModel model(calibrated_terms());
  MotorSimulator sim(model);
  sim.set_drive({400.0, 39500.0, 90.0, 0.0});  // large amplitude: slip and separation
  sim.advance(100000);
  int at_limit = 0;
  int separated = 0;
  for (int k = 0; k < 4000; ++k) {
    sim.step();
    const auto& f = sim.forces();
    if (f.normal_n > 1.0 && std::abs(std::abs(f.friction_n) - 0.35 * f.normal_n) < 1e-9) ++at_limit;
    if (24.8 - 2.58e7 * sim.state().q1_m <= 0.0) {
      ++separated;
      EXPECT_EQ(sim.state().contact_deflection_m, 0.0);
    }
  }
  EXPECT_GT(at_limit, 100);
  EXPECT_GT(separated, 100);
}

TEST(ImplicitCoulombGuide, HoldsBelowBreakawayAndSlidesAbove) {
  MotorParameters p{};
  p.mover.guide_friction_model = GuideFrictionModel::implicit_coulomb;
  p.contact.friction_coefficient = 0.0;  // only the guide acts on the mover
  const MotorModel model(p);
  const double breakaway = 0.04 * (24.8 - 2.58e7 * model.constants().static_q1_m + 9.81 * 0.2);
  MotorSimulator hold(model);
  hold.set_drive({0.0, 40000.0, 90.0, 0.95 * breakaway});
  hold.advance(200000);
  EXPECT_EQ(hold.state().mover_velocity_m_s, 0.0);
  EXPECT_EQ(hold.state().mover_position_m, 0.0);
  EXPECT_NEAR(hold.forces().guide_n, 0.95 * breakaway, 1e-9);  // balances the load exactly
  MotorSimulator slide(model);
  slide.set_drive({0.0, 40000.0, 90.0, 1.05 * breakaway});
  slide.advance(200000);
  EXPECT_LT(slide.state().mover_velocity_m_s, -1e-3);    // pushed backwards by the load
  EXPECT_NEAR(slide.forces().guide_n, breakaway, 1e-6);  // full Coulomb force opposes motion
}

// The calibrated contact (Jenkins element, implicit Coulomb guide) runs a step fused by hand
// (simulator_loop.h: advance_jenkins); it must be MotorSplitSystem's semi-implicit Euler step with
// another order of rounding. Reference: that step driven as the simulator drove it before issue
// 16 (phasor rotation, voltages, SpecialisedMotorSystem), from the same state, without the
// housekeeping (renormalisation and flush change nothing measurable in 3000 steps).
struct GenericRun {
  MotorSplitSystem::Vector q, v;
  double deflection_m;
};
GenericRun run_generic_step(const MotorModel& model, const DriveInput& drive, int steps) {
  MotorSplitSystem system(model.coefficients(), model.time_step_s());
  SpecialisedMotorSystem<TangentialContact::jenkins, GuideFrictionModel::implicit_coulomb> specialised{system};
  const MotorState rest = model.rest_state();
  MotorSplitSystem::Vector q{rest.q1_m, rest.q2_m, rest.mover_position_m};
  MotorSplitSystem::Vector v{rest.q1_dot_m_s, rest.q2_dot_m_s, rest.mover_velocity_m_s};
  const DriveWaveform w = make_drive_waveform(drive, model.coefficients().drive_amplitude_per_volt,
                                              model.time_step_s());
  double s = rest.drive_sin, c = rest.drive_cos, t = 0.0;
  for (int k = 0; k < steps; ++k) {
    system.set_inputs(drive_voltages(w, s, c), drive.load_n);
    semi_implicit_euler_step(specialised, t, model.time_step_s(), q, v);
    rotate_phasor(w, s, c);
    t += model.time_step_s();
  }
  return {q, v, system.contact_deflection_m()};
}

TEST(MotorSimulator, FusedJenkinsStepIsTheGenericStepToRounding) {
  const MotorModel model{test::calibrated_parameters()};
  ASSERT_EQ(model.coefficients().tangential, TangentialContact::jenkins);
  ASSERT_EQ(model.coefficients().guide_model, GuideFrictionModel::implicit_coulomb);
  constexpr int kSteps = 3000;  // 62 drive periods: contact, separation, stick and slip events
  for (const DriveInput drive : {DriveInput{400.0, 40000.0, 90.0, 0.0}, DriveInput{400.0, 39500.0, 90.0, 0.5},
                                 DriveInput{100.0, 40300.0, 90.0, 0.0}, DriveInput{50.0, 40000.0, -90.0, 0.0}}) {
    MotorSimulator sim(model);
    sim.set_drive(drive);
    sim.advance(kSteps);
    const GenericRun g = run_generic_step(model, drive, kSteps);
    const MotorState& f = sim.state();
    // Scales: 1 um for the modes (amplitudes are ~1-5 um), 1 m/s for their velocities.
    EXPECT_NEAR(f.q1_m, g.q[0], 1e-9 * 1e-6) << drive.amplitude_v << " V " << drive.frequency_hz << " Hz";
    EXPECT_NEAR(f.q2_m, g.q[1], 1e-9 * 1e-6);
    EXPECT_NEAR(f.q1_dot_m_s, g.v[0], 1e-9);
    EXPECT_NEAR(f.q2_dot_m_s, g.v[1], 1e-9);
    EXPECT_NEAR(f.mover_position_m, g.q[2], 1e-9 * 1e-6);
    EXPECT_NEAR(f.mover_velocity_m_s, g.v[2], 1e-9 * 1e-3);
    EXPECT_NEAR(f.contact_deflection_m, g.deflection_m, 1e-9 * 1e-6);
  }
}

// The same through the simulator over 50 ms (housekeeping, reseeds, every regime of the grid):
// numerics.step_kernel = "generic" runs MotorSplitSystem's step for the same motor. Rounding
// differences stay rounding-sized: the mover (which integrates everything) within 1e-9.
TEST(MotorSimulator, FusedAndGenericKernelsAgreeOverManyPeriods) {
  MotorParameters generic = test::calibrated_parameters();
  generic.numerics.step_kernel = StepKernel::generic;
  const MotorModel fused_model{test::calibrated_parameters()};
  const MotorModel generic_model{generic};
  for (const DriveInput drive : {DriveInput{400.0, 40000.0, 90.0, 0.0}, DriveInput{400.0, 39500.0, 90.0, 1.0},
                                 DriveInput{100.0, 40300.0, 90.0, 0.0}, DriveInput{50.0, 40000.0, 90.0, 0.0}}) {
    MotorSimulator a(fused_model), b(generic_model);
    a.set_drive(drive);
    b.set_drive(drive);
    const auto steps = static_cast<std::uint64_t>(0.05 / fused_model.time_step_s());
    a.advance(steps);
    b.advance(steps);
    EXPECT_NEAR(a.state().mover_position_m, b.state().mover_position_m,
                1e-9 * std::max(1e-6, std::abs(b.state().mover_position_m)))
        << drive.amplitude_v << " V " << drive.frequency_hz << " Hz";
    EXPECT_NEAR(a.state().q1_m, b.state().q1_m, 1e-9 * 1e-6);
    EXPECT_NEAR(a.state().q2_m, b.state().q2_m, 1e-9 * 1e-6);
    EXPECT_NEAR(a.forces().normal_n, b.forces().normal_n, 1e-9 * 100.0);
    EXPECT_NEAR(a.forces().friction_n, b.forces().friction_n, 1e-9 * 100.0);
    EXPECT_NEAR(a.forces().guide_n, b.forces().guide_n, 1e-9 * 100.0);
    EXPECT_EQ(a.state().time_s, b.state().time_s);
  }
}

// The fused step keeps the drive recurrence between calls: step() by step() is advance(n) bit
// for bit, also across drive changes (amplitude only, frequency, a repeated identical set_drive)
// at steps that are not block boundaries, and with a slow state evolving (thermal effect: the
// modal stiffness changes inside the cubic every block).
TEST(MotorSimulator, FusedJenkinsStepAndAdvanceAgreeAcrossDriveChanges) {
  MotorParameters p = test::calibrated_parameters();
  p.effects.thermal.enabled = true;
  p.effects.thermal.time_constant_s = 1e-3;  // fast enough to move in 10^4 steps
  p.effects.thermal.thermal_resistance_k_per_w = 50.0;
  const MotorModel model{p};
  MotorSimulator a(model), b(model);
  const DriveInput drives[] = {{400.0, 40000.0, 90.0, 0.0},
                               {300.0, 40000.0, 90.0, 0.0},   // amplitude only
                               {300.0, 40000.0, 90.0, 0.0},   // the same again
                               {300.0, 39600.0, 90.0, 0.2}};  // frequency and load
  const int lengths[] = {1001, 777, 1500, 2023};
  for (int i = 0; i < 4; ++i) {
    a.set_drive(drives[i]);
    b.set_drive(drives[i]);
    a.advance(static_cast<std::uint64_t>(lengths[i]));
    for (int k = 0; k < lengths[i]; ++k) b.step();
  }
  test::expect_same_state(a, b);
  EXPECT_GT(a.state().stator_temperature_rise_k, 0.0);
  EXPECT_EQ(a.state().stator_temperature_rise_k, b.state().stator_temperature_rise_k);
}

// Calls that change nothing change nothing, mid-run (not at a 64-step boundary): the drive
// recurrence is not reseeded by them. And a fault set and cleared mid-run leaves the recurrence
// exactly as if it had never been set (new amplitudes are replayed from the last anchor).
TEST(MotorSimulator, FusedJenkinsNoOpCallsMidRunChangeNoBit) {
  const MotorModel model{test::calibrated_parameters()};
  MotorSimulator a(model), b(model);
  const DriveInput drive{400.0, 40000.0, 90.0, 0.0};
  a.set_drive(drive);
  b.set_drive(drive);
  a.advance(10000);  // 10000 = 156 x 64 + 16: mid-block
  b.advance(10000);
  b.set_faults(ModelFaults{});
  b.set_slow_states(0.0, 0.0, false);
  b.set_drive(drive);
  b.set_faults({.phase_a_gain = 0.4, .preload_factor = 0.7, .guide_friction_factor = 1.0, .jammed = false});
  b.set_faults(ModelFaults{});
  a.advance(10001);
  b.advance(10001);
  test::expect_same_state(a, b);
}

// An amplitude change mid-run gives the same bits as the same change made by a simulator that
// took the steps in other chunks (the change lands on the same step).
TEST(MotorSimulator, FusedJenkinsAmplitudeChangeMidBlockIsChunkIndependent) {
  const MotorModel model{test::calibrated_parameters()};
  MotorSimulator a(model), b(model);
  a.set_drive({400.0, 40000.0, 90.0, 0.0});
  b.set_drive({400.0, 40000.0, 90.0, 0.0});
  a.advance(1000);
  for (int k = 0; k < 1000; ++k) b.step();
  a.set_drive({250.0, 40000.0, 90.0, 0.0});
  b.set_drive({250.0, 40000.0, 90.0, 0.0});
  a.advance(3000);
  b.advance(1500);
  b.advance(1500);
  test::expect_same_state(a, b);
}

// The NaN guard sees the mover too: a non-finite position from set_state() is reset at once,
// as the generic step does, and a NaN q1 does not leak a NaN normal force into the forces.
TEST(MotorSimulator, FusedJenkinsNanGuardCoversTheMover) {
  const MotorModel model{test::calibrated_parameters()};
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    MotorSimulator sim(model);
    sim.set_drive({300.0, 40000.0, 90.0, 0.0});
    sim.advance(1000);
    MotorState s = sim.state();
    s.mover_position_m = bad;
    sim.set_state(s);
    sim.step();
    EXPECT_TRUE(sim.diverged());
    EXPECT_TRUE(std::isfinite(sim.state().mover_position_m));
  }
  MotorSimulator sim(model);
  sim.set_drive({300.0, 40000.0, 90.0, 0.0});
  sim.advance(1000);
  MotorState s = sim.state();
  s.q1_m = std::numeric_limits<double>::quiet_NaN();
  sim.set_state(s);
  sim.step();
  EXPECT_TRUE(sim.diverged());
  EXPECT_FALSE(std::isnan(sim.forces().normal_n));
}

// A deflection outside the cone (set_state, or the cone narrowed by a lower preload or by wear)
// is handled as the generic step handles it: the force is clipped, the deflection's return
// mapping starts from where it is.
TEST(MotorSimulator, FusedJenkinsDeflectionOutsideTheConeAsTheGenericStep) {
  MotorParameters generic = test::calibrated_parameters();
  generic.numerics.step_kernel = StepKernel::generic;
  const MotorModel fused_model{test::calibrated_parameters()};
  const MotorModel generic_model{generic};
  MotorSimulator a(fused_model), b(generic_model);
  a.set_drive({300.0, 40000.0, 90.0, 0.0});
  b.set_drive({300.0, 40000.0, 90.0, 0.0});
  a.advance(5000);
  b.advance(5000);
  MotorState s = b.state();
  s.contact_deflection_m = 5.0 * s.contact_deflection_m + 1e-7;
  a.set_state(s);
  b.set_state(s);
  a.step();
  b.step();
  EXPECT_NEAR(a.state().contact_deflection_m, b.state().contact_deflection_m, 1e-15);
  EXPECT_NEAR(a.forces().friction_n, b.forces().friction_n, 1e-9);
  a.advance(3000);
  b.advance(3000);
  EXPECT_NEAR(a.state().mover_position_m, b.state().mover_position_m, 1e-15);
}

// Wear lowers mu_c every block while the motor runs: the fused and generic steps agree.
TEST(MotorSimulator, FusedJenkinsUnderWearAsTheGenericStep) {
  MotorParameters p = test::calibrated_parameters();
  p.effects.wear.enabled = true;
  p.effects.wear.friction_change = -0.9;
  p.effects.wear.run_in_distance_m = 1e-3;  // run in within a few ms at 0.6 m/s
  MotorParameters g = p;
  g.numerics.step_kernel = StepKernel::generic;
  const MotorModel fused_model{p}, generic_model{g};
  MotorSimulator a(fused_model), b(generic_model);
  a.set_drive({400.0, 40000.0, 90.0, 0.0});
  b.set_drive({400.0, 40000.0, 90.0, 0.0});
  a.advance(20000);
  b.advance(20000);
  EXPECT_GT(a.state().sliding_distance_m, 1e-3);
  EXPECT_NEAR(a.state().mover_position_m, b.state().mover_position_m, 1e-9 * std::abs(b.state().mover_position_m));
  EXPECT_NEAR(a.state().contact_deflection_m, b.state().contact_deflection_m, 1e-15);
}

}  // namespace
}  // namespace swum
