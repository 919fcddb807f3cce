#include "analysis/steady_state/steady_state.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../thread_pool_for.h"
#include "formats/parameter_file.h"
#include "test_paths.h"

namespace swum {
namespace {

// The paper reference set (MotorParameters{}) reads the paper's voltages as peak-to-peak
// (model_spec §0): its "400 V" is a 200 V terminal amplitude, the model's input.
constexpr double literal_v(double paper_v) {
  return amplitude_v_of_paper_voltage(PaperVoltageAxis::peak_to_peak, paper_v);
}

const MotorModel& reference_model() {
  static const MotorModel model{MotorParameters{}};
  return model;
}

const MotorModel& calibrated_model() {
  static const MotorModel model{[] {
    std::ifstream in(swum::test::source_path("config/li2019.toml"));
    std::stringstream text;
    text << in.rdbuf();
    return parse_motor_parameters(text.str(), "li2019.toml");
  }()};
  return model;
}

void expect_rel(double actual, double expected, double rel, const char* what) {
  EXPECT_NEAR(actual, expected, std::abs(expected) * rel) << what;
}

// Fixed-step solver against the adaptive reference, over the SAME window (settle 30 ms, then
// exactly two 10 ms windows; the last one is compared), so that the difference is the
// discretisation error only and not a different averaging interval.
struct Comparison {
  SteadyStateResult fixed, ref;
};
Comparison run_both(const MotorModel& model, const OperatingPoint& point) {
  SteadyStateOptions opt;
  opt.max_s = opt.settle_s + 2.0 * opt.window_s;
  opt.speed_tolerance_mm_s = 1e9;  // always two windows
  opt.reference_relative_tolerance = 1e-8;
  return {run_to_steady_state(model, point, opt), run_to_steady_state_reference(model, point, opt)};
}

void compare_with_reference(const MotorModel& model, const OperatingPoint& point, double speed_rel,
                            double amplitude_rel) {
  const auto [fixed, ref] = run_both(model, point);
  ASSERT_TRUE(fixed.ok) << fixed.failure;
  ASSERT_TRUE(ref.ok) << ref.failure;
  ASSERT_EQ(fixed.windows, ref.windows);
  expect_rel(fixed.speed_mm_s, ref.speed_mm_s, speed_rel, "speed");
  expect_rel(fixed.tip_normal_um, ref.tip_normal_um, amplitude_rel, "tip normal");
  expect_rel(fixed.tip_tangential_um, ref.tip_tangential_um, amplitude_rel, "tip tangential");
  EXPECT_NEAR(fixed.contact_fraction, ref.contact_fraction, 0.02);
  std::printf("  %g V %g Hz %g N: speed %+.3f %%, tip normal %+.3f %%, tip tangential %+.3f %%\n", point.amplitude_v,
              point.frequency_hz, point.load_n, 100.0 * (fixed.speed_mm_s / ref.speed_mm_s - 1.0),
              100.0 * (fixed.tip_normal_um / ref.tip_normal_um - 1.0),
              100.0 * (fixed.tip_tangential_um / ref.tip_tangential_um - 1.0));
}
void compare_with_reference(const MotorModel& model, double amplitude_v, double f_hz, double speed_rel,
                            double amplitude_rel) {
  compare_with_reference(model, OperatingPoint{amplitude_v, f_hz}, speed_rel, amplitude_rel);
}

// The accuracy contract of the fixed step (issue 16): 1 % on speed and tip amplitudes against
// the adaptive reference at the calibrated config (config/li2019.toml, its time step and
// scheme), every point started from rest. The grid: the drift-aware frequencies (speed maxima
// 40.3 / 39.9 / 39.5 kHz at 100 / 250 / 400 V), both flanks of the 100 V and 400 V speed
// peaks (the 400 V fold lies between 39.375 and 39.4 kHz: 39.4 kHz is its upper edge), two
// loaded points, and drives at exactly 40 kHz at four voltages and two loads: with a whole
// number of steps per drive period the stick-slip and separation events fall on the same step
// phases in every period, so their timing errors do not average out and the error there
// varies erratically with the step count (docs/performance.md; at 40.05 kHz it is a smooth
// O(dt^2) bias). Worst errors at 48 steps per 40 kHz period (the config's step since issue 16):
// speed +0.99 % (250 V, 40 kHz), tip normal +0.29 %, tip tangential +0.47 % (100 V,
// 40.45 kHz). 44 steps would pass too (speed within 0.80 %; 40, 42 and 43 fail at 100 V,
// 40 kHz), but the SIMD lanes run settle and window lengths of whole 64-step blocks only, and
// the fits' 5 ms windows (measured_point_model.h) are whole blocks only when the steps per
// 40 kHz period are a multiple of 8 (docs/performance.md); ~0.8 s of reference per point.
struct GridPoint {
  double amplitude_v, f_hz, load_n;
};
class SteadyStateContract : public ::testing::TestWithParam<GridPoint> {};

TEST_P(SteadyStateContract, FixedStepWithinOnePercentOfReference) {
  const GridPoint& p = GetParam();
  compare_with_reference(calibrated_model(), OperatingPoint{p.amplitude_v, p.f_hz, p.load_n}, 0.01, 0.01);
}

std::string grid_point_name(const ::testing::TestParamInfo<GridPoint>& info) {
  const GridPoint& p = info.param;
  std::string name = std::to_string(static_cast<int>(p.amplitude_v)) + "V_" + std::to_string(static_cast<int>(p.f_hz)) +
                     "Hz";
  if (p.load_n > 0.0) name += "_" + std::to_string(static_cast<int>(1000.0 * p.load_n)) + "mN";
  return name;
}

INSTANTIATE_TEST_SUITE_P(ValidationGrid, SteadyStateContract,
                         ::testing::Values(GridPoint{100.0, 40000.0, 0.0}, GridPoint{100.0, 40300.0, 0.0},
                                           GridPoint{250.0, 39900.0, 0.0}, GridPoint{250.0, 40200.0, 0.0},
                                           GridPoint{400.0, 39500.0, 0.0}, GridPoint{400.0, 40000.0, 0.0},
                                           // flanks of the speed peaks
                                           GridPoint{100.0, 40150.0, 0.0}, GridPoint{100.0, 40450.0, 0.0},
                                           GridPoint{400.0, 39400.0, 0.0}, GridPoint{400.0, 39600.0, 0.0},
                                           // loaded
                                           GridPoint{400.0, 40000.0, 1.0}, GridPoint{250.0, 39900.0, 0.5},
                                           // a whole number of steps per drive period
                                           GridPoint{250.0, 40000.0, 0.0}, GridPoint{300.0, 40000.0, 0.0},
                                           GridPoint{300.0, 40000.0, 1.0}),
                         grid_point_name);

// The speed-peak frequency of the fixed step within one grid step (25 Hz) of the reference's, on
// a 25 Hz grid across the peak (100 V: 40.2-40.4 kHz, a flat maximum; 400 V: 39.375-39.525
// kHz, the maximum just above the fold, where the speed falls from +800 to -80 mm/s). 25 Hz is
// a tenth of the half-width of the 100 V peak and below the 0.2 kHz uncertainty of the
// paper's peak. At 48 (and 44, 64) steps per period both peaks coincide (40.275 and 39.45 kHz). ~7 s of reference per
// peak.
struct PeakGrid {
  double amplitude_v, f_first_hz, f_last_hz;
};
class SteadyStatePeak : public ::testing::TestWithParam<PeakGrid> {};

TEST_P(SteadyStatePeak, PeakFrequencyWithinOneGridStepOfReference) {
  constexpr double kGridHz = 25.0;
  const PeakGrid& g = GetParam();
  // The grid's points are independent: computed two at a time (one per core; the adaptive
  // reference dominates, ~7 s per peak, a minute under the sanitizers), then read in order.
  std::vector<double> grid;
  for (double f = g.f_first_hz; f <= g.f_last_hz + 1.0; f += kGridHz) grid.push_back(f);
  std::vector<Comparison> runs(grid.size());
  std::atomic<std::size_t> next{0};
  const auto run_points = [&] {
    for (std::size_t k = next++; k < grid.size(); k = next++)
      runs[k] = run_both(calibrated_model(), {g.amplitude_v, grid[k]});
  };
  test::on_two_threads([&](int) { run_points(); });
  double best_fixed = -1e300, best_ref = -1e300, f_fixed = 0.0, f_ref = 0.0;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const double f = grid[k];
    const auto& [fixed, ref] = runs[k];
    ASSERT_TRUE(fixed.ok) << fixed.failure;
    ASSERT_TRUE(ref.ok) << ref.failure;
    std::printf("  %g V %g Hz: fixed %.2f mm/s, reference %.2f mm/s\n", g.amplitude_v, f, fixed.speed_mm_s,
                ref.speed_mm_s);
    if (fixed.speed_mm_s > best_fixed) {
      best_fixed = fixed.speed_mm_s;
      f_fixed = f;
    }
    if (ref.speed_mm_s > best_ref) {
      best_ref = ref.speed_mm_s;
      f_ref = f;
    }
  }
  EXPECT_GT(f_ref, g.f_first_hz) << "the reference peak must lie inside the grid";
  EXPECT_LT(f_ref, g.f_last_hz) << "the reference peak must lie inside the grid";
  EXPECT_LE(std::abs(f_fixed - f_ref), kGridHz + 1e-6)
      << "fixed-step peak " << f_fixed << " Hz, reference " << f_ref << " Hz";
}

INSTANTIATE_TEST_SUITE_P(SpeedPeaks, SteadyStatePeak,
                         ::testing::Values(PeakGrid{100.0, 40200.0, 40400.0}, PeakGrid{400.0, 39375.0, 39525.0}),
                         [](const ::testing::TestParamInfo<PeakGrid>& info) {
                           return std::to_string(static_cast<int>(info.param.amplitude_v)) + "V";
                         });

// Rigid contact (paper reference set): the stick/slip events of the rigid Coulomb contact
// leave a first-order error in B2 and the speed (-3.3 % / -4.4 % at 96 steps per cycle,
// -1.3 % / -1.6 % at 192); only the L1 amplitude is second order. Documented, not a target.
TEST(SteadyStateReference, RigidContactConvergesFirstOrder) {
  MotorParameters p{};
  p.numerics.time_step_ns = 1e9 / (384.0 * 40000.0);
  const MotorModel fine(p);
  compare_with_reference(fine, literal_v(250.0), 40200.0, 0.01, 0.01);
  compare_with_reference(reference_model(), literal_v(400.0), 40000.0, 0.05, 0.04);
}

TEST(SteadyState, ReproducesModelSpecSection92) {
  const auto& m = reference_model();
  const auto v400 = run_to_steady_state(m, {literal_v(400.0), 40000.0});
  ASSERT_TRUE(v400.ok) << v400.failure;
  EXPECT_NEAR(v400.speed_mm_s, 198.0, 8.0);  // spec: 195 (sweep) .. 201 (max)
  EXPECT_GT(v400.contact_fraction, 0.4);
  EXPECT_LT(v400.contact_fraction, 0.8);  // intermittent contact
  const auto v250 = run_to_steady_state(m, {literal_v(250.0), 40200.0});
  EXPECT_NEAR(v250.speed_mm_s, 74.0, 4.0);
  const auto v300 = run_to_steady_state(m, {literal_v(300.0), 40000.0});
  EXPECT_NEAR(v300.speed_mm_s, 0.0, 1.0);  // dead zone up to 325 V at 40 kHz
  const auto v350 = run_to_steady_state(m, {literal_v(350.0), 40000.0});
  EXPECT_NEAR(v350.speed_mm_s, 173.0, 15.0);
}

TEST(SteadyState, ExactErfRootEqualsCoulombProjection) {
  MotorParameters p{};
  p.numerics.friction_solver = FrictionSolver::erf_newton;
  const MotorModel erf_model(p);
  const auto a = run_to_steady_state(reference_model(), {literal_v(400.0), 40000.0});
  const auto b = run_to_steady_state(erf_model, {literal_v(400.0), 40000.0});
  EXPECT_NEAR(b.speed_mm_s, a.speed_mm_s, 1e-4 * a.speed_mm_s);
  EXPECT_NEAR(b.tip_tangential_um, a.tip_tangential_um, 1e-4 * a.tip_tangential_um);
}

TEST(SteadyState, PhaseSignReversesDirection) {
  const auto fwd = run_to_steady_state(reference_model(), {literal_v(400.0), 40000.0, 0.0, 90.0});
  const auto rev = run_to_steady_state(reference_model(), {literal_v(400.0), 40000.0, 0.0, -90.0});
  EXPECT_GT(fwd.speed_mm_s, 100.0);
  EXPECT_NEAR(rev.speed_mm_s, -fwd.speed_mm_s, 0.02 * fwd.speed_mm_s);
}

TEST(SteadyState, LoadSlowsTheMover) {
  const auto free = run_to_steady_state(reference_model(), {literal_v(400.0), 40000.0, 0.0});
  const auto loaded = run_to_steady_state(reference_model(), {literal_v(400.0), 40000.0, 1.0});
  EXPECT_LT(loaded.speed_mm_s, free.speed_mm_s - 5.0);
}

TEST(SteadyState, LinearModelDoesNotMoveAt40kHz) {
  const MotorModel linear{linearised(MotorParameters{})};
  const auto r = run_to_steady_state(linear, {literal_v(400.0), 40000.0});
  EXPECT_LT(std::abs(r.speed_mm_s), 5.0);  // §9.2: 40 kHz is below the linear contact resonance
}

TEST(SteadyState, FrictionDoesNotChatterInStick) {
  // 100 V at 40.4 kHz: B2 locked by friction (§9.3), the contact sticks.
  std::vector<double> ft;
  std::vector<double> fn;
  SteadyStateOptions opt;
  opt.settle_s = 0.005;
  opt.window_s = 0.002;
  opt.max_s = 0.009;
  opt.trace_every_steps = 1;
  opt.trace = [&](const TraceSample& s) {
    if (s.time_s > 0.005) {
      ft.push_back(s.friction_force_n);
      fn.push_back(s.normal_force_n);
    }
  };
  const auto r = run_to_steady_state(reference_model(), {literal_v(100.0), 40400.0}, opt);
  ASSERT_GT(ft.size(), 1000U);
  double jump = 0.0;
  double limit = 0.0;
  for (std::size_t k = 1; k < ft.size(); ++k) {
    jump += std::abs(ft[k] - ft[k - 1]);
    limit += 0.35 * fn[k];
  }
  jump /= static_cast<double>(ft.size() - 1);
  limit /= static_cast<double>(ft.size() - 1);
  EXPECT_LT(jump, 0.1 * limit) << "F_T changes by " << jump << " N per step; cone " << limit;
  EXPECT_LT(r.tip_tangential_um, 0.05);  // B2 locked
  EXPECT_LT(std::abs(r.speed_mm_s), 2.0);
}

TEST(SteadyState, TraceIsSampledEveryNSteps) {
  int samples = 0;
  SteadyStateOptions opt;
  opt.settle_s = 0.001;
  opt.window_s = 0.001;
  opt.max_s = 0.0021;
  opt.trace_every_steps = 96;
  opt.trace = [&](const TraceSample&) { ++samples; };
  const auto r = run_to_steady_state(reference_model(), {literal_v(200.0), 40000.0}, opt);
  EXPECT_EQ(static_cast<std::uint64_t>(samples), r.steps / 96);
}

// Issue 16 item 3: `swum simulate --duration-s 2` ran 1.99 s of settling and one window, then
// said "did not settle ... last two windows differ by 0.000000 mm/s" (one window cannot
// disagree with anything). A run of at most 2 s stops as soon as two windows agree.
TEST(SteadyState, RunWithinADurationStopsWhenTwoWindowsAgree) {
  const SteadyStateOptions opt = steady_state_options_within(2.0);
  const auto r = run_to_steady_state(calibrated_model(), {400.0, 40000.0}, opt);
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_GE(r.windows, 2);
  EXPECT_LE(r.sim_s, 0.1 + 1e-9);  // settle 30 ms + a few 10 ms windows, not 2 s
  EXPECT_NEAR(r.sim_s, static_cast<double>(r.steps) * calibrated_model().time_step_s(), 1e-9);
  // Short durations still fit two windows.
  for (const double d : {0.004, 0.02, 0.05}) {
    const SteadyStateOptions o = steady_state_options_within(d);
    EXPECT_GE(o.settle_s, 0.0);
    EXPECT_LE(o.settle_s + 2.0 * o.window_s, d + 1e-12) << d;
    EXPECT_DOUBLE_EQ(o.max_s, d);
  }
}

// stop_when_settled = false (swum simulate --whole-duration, issue 16: a real-time factor counts
// time actually run): every window up to max_s is run, the result is the last one and ok says
// whether it agrees with the one before; the same settled values as the early stop, within the
// agreement tolerance.
TEST(SteadyState, WholeDurationRunsEveryWindowAndReportsTheLast) {
  SteadyStateOptions whole = steady_state_options_within(0.2);
  whole.stop_when_settled = false;
  const auto r = run_to_steady_state(calibrated_model(), {400.0, 40000.0}, whole);
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_NEAR(r.sim_s, 0.2, 1e-9);
  EXPECT_EQ(r.windows, 17);  // (0.2 s - 30 ms settle) / 10 ms
  const auto early = run_to_steady_state(calibrated_model(), {400.0, 40000.0}, steady_state_options_within(0.2));
  ASSERT_TRUE(early.ok);
  EXPECT_LT(early.sim_s, 0.1);
  EXPECT_NEAR(r.speed_mm_s, early.speed_mm_s, 0.01 * early.speed_mm_s);
  EXPECT_NEAR(r.tip_normal_um, early.tip_normal_um, 0.005 * early.tip_normal_um);
  // A run that never settles within max_s still says so.
  SteadyStateOptions strict = whole;
  strict.speed_tolerance_mm_s = -1.0;
  strict.speed_relative_tolerance = -1.0;
  const auto never = run_to_steady_state(calibrated_model(), {400.0, 40000.0}, strict);
  EXPECT_FALSE(never.ok);
  EXPECT_NEAR(never.sim_s, 0.2, 1e-9);
  EXPECT_NE(never.failure.find("did not settle"), std::string::npos) << never.failure;
}

TEST(SteadyState, OneWindowIsNotReportedAsTwoThatDiffer) {
  SteadyStateOptions opt;
  opt.settle_s = 0.005;
  opt.window_s = 0.005;
  opt.max_s = 0.012;  // room for one window only
  const auto r = run_to_steady_state(calibrated_model(), {400.0, 40000.0}, opt);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.windows, 1);
  EXPECT_EQ(r.failure.find("last two windows"), std::string::npos) << r.failure;
  EXPECT_NE(r.failure.find("one window"), std::string::npos) << r.failure;
}

TEST(SteadyState, DivergenceIsReportedNotThrown) {
  MotorParameters p{};
  // The modal part is unconditionally stable (dispersion-corrected inertia); a contact 4e4 x
  // stiffer than Table 3 with a 20 us step is not (w dt ~ 60 > 2).
  p.numerics.time_step_ns = 20000.0;
  p.contact.stiffness_n_m = 1e12;
  const MotorModel model(p);
  SteadyStateOptions opt;
  opt.settle_s = 0.01;
  const auto r = run_to_steady_state(model, {literal_v(400.0), 40000.0}, opt);
  EXPECT_TRUE(r.diverged);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.failure.empty());
}

}  // namespace
}  // namespace swum
