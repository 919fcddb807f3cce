// amplifier_sizing.h on band rows made by hand: the figures at the pick interpolated between the
// grid points either side, the worst cases and where they are, the network sized at the design
// row and what the amplifier then sees at the other rows (the matching maths of
// matching_network.h: a parallel inductor that cancels the susceptance leaves the current in
// phase; a series one needs V R/|Z| from the amplifier).
#include "analysis/sizing/amplifier_sizing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>

namespace swum {
namespace {

constexpr double kC0 = 10e-9;

// The readings of one phase pair at voltage v for admittance y (both phases alike, B scaled by
// b_scale so that the phases differ), with RMS and peak as a sinusoid has them.
ElectricalReadings readings(double v, std::complex<double> y, double b_scale = 1.0) {
  ElectricalReadings e;
  e.valid = true;
  auto set = [&](std::complex<double> yy, double& amplitude, double& phase, double& rms, double& peak, double& voltage,
                 double& power, double& apparent, double& pf) {
    amplitude = std::abs(yy) * v;
    phase = std::arg(yy) * 180.0 / std::numbers::pi;
    rms = amplitude / std::numbers::sqrt2;
    peak = amplitude;
    voltage = v;
    power = 0.5 * v * v * yy.real();
    apparent = v / std::numbers::sqrt2 * rms;
    pf = power / apparent;
  };
  set(y, e.current_a_a, e.phase_a_deg, e.rms_current_a_a, e.peak_current_a_a, e.voltage_a_v, e.power_a_w,
      e.apparent_power_a_va, e.power_factor_a);
  set({y.real(), y.imag() * b_scale}, e.current_b_a, e.phase_b_deg, e.rms_current_b_a, e.peak_current_b_a,
      e.voltage_b_v, e.power_b_w, e.apparent_power_b_va, e.power_factor_b);
  e.motional_phase_a_deg = e.motional_phase_b_deg = -30.0;
  return e;
}

// A row whose curve holds two grid points, `high` and `low` Hz, with the given admittances; the pick
// at `pick_hz`.
BandRow row(double v, double load_n, double high, std::complex<double> y_high, double low, std::complex<double> y_low,
            double pick_hz, double b_scale = 1.0) {
  BandRow r;
  r.amplitude_v = v;
  r.load_n = load_n;
  r.curve = {CurveSample{high, 300.0}, CurveSample{low, 320.0}};
  r.points.resize(2);
  r.points[0].electrical = readings(v, y_high, b_scale);
  r.points[1].electrical = readings(v, y_low, b_scale);
  r.points[0].damping_power_w = 4.0;
  r.points[1].damping_power_w = 6.0;
  r.pick.decided = true;
  r.pick.frequency_hz = pick_hz;
  r.pick.speed_mm_s = 310.0;
  r.pick.peak_frequency_hz = low - 100.0;
  return r;
}

TEST(AmplifierSizing, FiguresAtThePickAreInterpolatedBetweenTheGridPointsEitherSide) {
  const std::complex<double> y_high{1e-3, 3e-3}, y_low{2e-3, 4e-3};
  const std::vector<BandRow> rows = {row(200.0, 1.0, 40100.0, y_high, 40075.0, y_low, 40090.0)};
  const SizingResult s = size_amplifier(rows, kC0, 0);
  ASSERT_TRUE(s.rows[0].sized) << s.rows[0].reason;
  // band_electrical_at's interpolation: amplitude and phase each linearly (t = 10/25 of the way down).
  const double t = 10.0 / 25.0;
  const double amplitude = 200.0 * ((1.0 - t) * std::abs(y_high) + t * std::abs(y_low));
  const double phase_deg = ((1.0 - t) * std::arg(y_high) + t * std::arg(y_low)) * 180.0 / std::numbers::pi;
  EXPECT_NEAR(s.rows[0].a.current_amplitude_a, amplitude, 1e-9);
  EXPECT_NEAR(s.rows[0].a.phase_deg, phase_deg, 1e-9);
  EXPECT_NEAR(std::abs(s.rows[0].a.admittance_siemens) * 200.0, amplitude, 1e-9);
  EXPECT_NEAR(std::arg(s.rows[0].a.admittance_siemens) * 180.0 / std::numbers::pi, phase_deg, 1e-9);
  EXPECT_NEAR(s.rows[0].stator_heat_w, 4.8, 1e-12);
  EXPECT_NEAR(s.rows[0].mechanical_power_w, 1.0 * 0.310, 1e-12);
  EXPECT_NEAR(s.rows[0].electrical_power_w, 2 * (0.6 * 0.5 * 4e4 * 1e-3 + 0.4 * 0.5 * 4e4 * 2e-3), 1e-9);
  EXPECT_NEAR(s.rows[0].efficiency, s.rows[0].mechanical_power_w / s.rows[0].electrical_power_w, 1e-12);
  EXPECT_LE(s.rows[0].a.power_factor, 1.0);
}

TEST(AmplifierSizing, AParallelInductorSizedAtTheDesignRowLeavesTheAmplifierCurrentInPhaseThere) {
  const std::complex<double> y{1.5e-3, 3.2e-3};
  const std::vector<BandRow> rows = {row(400.0, 0.0, 39700.0, y, 39675.0, y, 39680.0),
                                     row(100.0, 0.0, 40500.0, {0.5e-3, 2.7e-3}, 40475.0, {0.5e-3, 2.7e-3}, 40480.0)};
  const std::size_t design = default_design_row(rows);
  ASSERT_EQ(design, 0u);  // the highest voltage
  const SizingResult s = size_amplifier(rows, kC0, design);
  ASSERT_TRUE(s.designed);
  const double w = 2.0 * std::numbers::pi * 39680.0;
  EXPECT_NEAR(s.design_a.parallel_inductance_h, 1.0 / (w * y.imag()), 1e-12);
  EXPECT_NEAR(s.design_a.c0_parallel_inductance_h, 1.0 / (w * w * kC0), 1e-12);
  EXPECT_NEAR(s.rows[0].matched_a.parallel_current_phase_deg, 0.0, 1e-9);
  EXPECT_NEAR(s.rows[0].matched_a.parallel_current_amplitude_a, y.real() * 400.0, 1e-9);
  // At the other row the same inductor leaves a phase: the detuned motor seen by the fixed network.
  EXPECT_GT(std::abs(s.rows[1].matched_a.parallel_current_phase_deg), 5.0);
  // Series matching: the amplifier sees R alone and puts out V R/|Z| for V at the phase.
  const std::complex<double> z = 1.0 / y;
  EXPECT_NEAR(s.rows[0].matched_a.series_source_voltage_v, 400.0 * z.real() / std::abs(z), 1e-6);
  EXPECT_NEAR(s.rows[0].matched_a.series_current_phase_deg, 0.0, 1e-9);
  EXPECT_LT(s.rows[0].matched_a.series_source_voltage_v, 400.0);  // a series inductor steps the voltage up
}

TEST(AmplifierSizing, WorstCasesNameTheirRowAndPhase) {
  const std::vector<BandRow> rows = {row(100.0, 0.0, 40500.0, {0.5e-3, 2.7e-3}, 40475.0, {0.5e-3, 2.7e-3}, 40480.0),
                                     row(300.0, 2.0, 39900.0, {1e-3, 3e-3}, 39875.0, {1e-3, 3e-3}, 39880.0, 1.2)};
  const SizingResult s = size_amplifier(rows, kC0, default_design_row(rows));
  ASSERT_TRUE(s.summary.current_rms_a.known);
  EXPECT_EQ(s.summary.current_rms_a.row, 1u);
  EXPECT_EQ(s.summary.current_rms_a.phase, 'b');  // phase B's susceptance is 1.2x A's there
  EXPECT_EQ(s.summary.mechanical_power_w.row, 1u);
  EXPECT_EQ(s.summary.sized, 2u);
}

TEST(AmplifierSizing, AnUndecidedRowOrAFailedNeighbourIsNotSizedAndSaysWhy) {
  BandRow undecided = row(100.0, 0.0, 40500.0, {0.5e-3, 2.7e-3}, 40475.0, {0.5e-3, 2.7e-3}, 40480.0);
  undecided.pick.decided = false;
  undecided.pick.reason = "no peak";
  BandRow failed = row(200.0, 0.0, 40100.0, {1e-3, 3e-3}, 40075.0, {1e-3, 3e-3}, 40080.0);
  failed.points[1].electrical.valid = false;
  const SizingResult s = size_amplifier({undecided, failed}, kC0, 1);
  EXPECT_FALSE(s.rows[0].sized);
  EXPECT_NE(s.rows[0].reason.find("no peak"), std::string::npos);
  EXPECT_FALSE(s.rows[1].sized);
  EXPECT_NE(s.rows[1].reason.find("electrical port"), std::string::npos);
  EXPECT_FALSE(s.designed);
  EXPECT_EQ(s.summary.sized, 0u);
}

// The population's figure: the needed-th smallest of the motors' worst cases; a rejected draw, a
// motor with an unsized row or a worst case never found is never within.
TEST(AmplifierSizing, APopulationFigureIsTheWorstCaseThatTheNeededShareOfMotorsStaysWithin) {
  std::vector<SizingResult> motors(5);
  const double worst_rms[] = {4.0, 2.0, 3.0, 1.0, 5.0};
  for (std::size_t i = 0; i < motors.size(); ++i) {
    SizingResult& m = motors[i];
    m.rows.resize(1);
    m.rows[0].sized = true;
    m.rows[0].frequency_hz = 40000.0 + 10.0 * static_cast<double>(i);
    m.summary.sized = 1;
    m.summary.current_rms_a = Extreme{true, worst_rms[i], 0, 'a'};
    if (i != 2) m.summary.parallel_current_amplitude_a = Extreme{true, 0.1 * worst_rms[i], 0, 'a'};
  }
  motors[4].summary.sized = 0;  // the motor with the largest current has a row not sized
  std::vector<const SizingResult*> pointers;
  for (const SizingResult& m : motors) pointers.push_back(&m);
  pointers.push_back(nullptr);  // a rejected draw
  const PopulationSizing half = size_population(pointers, 0.5);
  EXPECT_EQ(half.motors, 6u);
  EXPECT_EQ(half.sized, 4u);
  EXPECT_EQ(half.needed, 3u);
  ASSERT_TRUE(half.current_rms_a.reached);
  EXPECT_EQ(half.current_rms_a.value, 3.0);  // 1, 2, 3 of the sized motors' 1, 2, 3, 4
  ASSERT_TRUE(half.parallel_current_amplitude_a.reached);
  EXPECT_NEAR(half.parallel_current_amplitude_a.value, 0.4, 1e-12);  // 0.1, 0.2, 0.4; motor 2 has none
  EXPECT_TRUE(half.oscillator_reached);
  EXPECT_EQ(half.oscillator_covered, 3u);
  const PopulationSizing most = size_population(pointers, 4.0 / 6.0);
  EXPECT_EQ(most.needed, 4u);
  EXPECT_TRUE(most.current_rms_a.reached);
  EXPECT_EQ(most.current_rms_a.value, 4.0);
  EXPECT_FALSE(most.parallel_current_amplitude_a.reached);  // only three motors have one
  const PopulationSizing all = size_population(pointers, 1.0);
  EXPECT_FALSE(all.current_rms_a.reached);
  EXPECT_FALSE(all.oscillator_reached);
}

}  // namespace
}  // namespace swum
