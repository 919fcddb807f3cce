// operating_band on the calibrated motor (config/li2019.toml) and on it with a thermal effect whose
// stiffness falls with temperature: physical facts of the band an oscillator must cover.
#include "analysis/operating_point/operating_band.h"

#include <gtest/gtest.h>

#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "../thread_pool_for.h"
#include "calibrated_parameters.h"

namespace swum {
namespace {

// li2019 + [effects.thermal] enabled = true, stiffness_coefficient_per_k = -5e-4,
// damping_coefficient_per_k = 1e-3: the resonance falls as the stator warms (docs/discrepancy.md).
MotorParameters li2019_softening_when_hot() {
  MotorParameters p = test::calibrated_parameters();
  p.effects.thermal.enabled = true;
  p.effects.thermal.stiffness_coefficient_per_k = -5e-4;
  p.effects.thermal.damping_coefficient_per_k = 1e-3;
  return p;
}

// Coarse, to keep the test short: the peaks at 100 and 400 V and 400 V 50 K warmer, their
// collapses below and peak + margin above.
BandGrid coarse_grid(std::vector<double> voltages, std::vector<double> rises_k = {0.0}) {
  BandGrid grid;
  grid.voltages = std::move(voltages);
  grid.temperature_rises_k = std::move(rises_k);
  for (double f = 38750.0; f <= 40500.0 + 1e-9; f += 50.0) grid.frequencies_hz.push_back(f);
  grid.margin_hz = 100.0;
  return grid;
}

const BandRow& row_at(const std::vector<BandRow>& rows, double amplitude_v, double rise_k = 0.0) {
  for (const BandRow& r : rows) {
    if (r.amplitude_v == amplitude_v && r.temperature_rise_k == rise_k) return r;
  }
  throw std::logic_error("no row");
}

TEST(OperatingBand, PicksAMarginAboveTheSofteningPeakAndThePeakFallsWithVoltage) {
  const MotorModel model(test::calibrated_parameters());
  const auto rows = operating_band(model, coarse_grid({100.0, 400.0}), test::two_thread_for, 2);
  ASSERT_EQ(rows.size(), 2u);
  const BandRow& low = row_at(rows, 100.0);
  const BandRow& high = row_at(rows, 400.0);
  ASSERT_TRUE(low.pick.decided) << low.pick.reason;
  ASSERT_TRUE(high.pick.decided) << high.pick.reason;
  // At 400 V the pick sits at least the margin above the peak, on the stable high side.
  EXPECT_GE(high.pick.frequency_hz, high.pick.peak_frequency_hz + 100.0) << high.pick.reason;
  ASSERT_TRUE(high.pick.collapse_hz.has_value()) << "a down-sweep jumps below a softening peak";
  EXPECT_LT(*high.pick.collapse_hz, high.pick.peak_frequency_hz);
  // Softening: the peak drifts down as the drive grows (docs/validation.md).
  EXPECT_GT(low.pick.peak_frequency_hz, high.pick.peak_frequency_hz + 300.0)
      << low.pick.peak_frequency_hz << " vs " << high.pick.peak_frequency_hz;
  // The curve is the chain's: every grid point, highest first.
  ASSERT_EQ(high.curve.size(), 36u);
  EXPECT_EQ(high.curve.front().frequency_hz, 40500.0);
  EXPECT_EQ(high.curve.back().frequency_hz, 38750.0);

  // Every curve point's steady state, in the curve's order, with the electrical port: at the
  // pick the figures between those of the grid points either side, real power flowing in.
  ASSERT_EQ(high.points.size(), high.curve.size());
  const std::optional<ElectricalReadings> at_pick = band_electrical_at(high, high.pick.frequency_hz);
  ASSERT_TRUE(at_pick.has_value());
  EXPECT_GT(at_pick->power_a_w + at_pick->power_b_w, 0.0);
  for (std::size_t k = 1; k < high.curve.size(); ++k) {
    if (high.curve[k].frequency_hz > high.pick.frequency_hz) continue;
    const double above = high.points[k - 1].electrical.rms_current_a_a;
    const double below = high.points[k].electrical.rms_current_a_a;
    EXPECT_GE(at_pick->rms_current_a_a, std::min(above, below));
    EXPECT_LE(at_pick->rms_current_a_a, std::max(above, below));
    break;
  }

  const BandSummary s = summarize_band(rows);
  EXPECT_EQ(s.decided, 2u);
  EXPECT_EQ(s.undecided, 0u);
  ASSERT_TRUE(s.band && s.peak);
  EXPECT_EQ(s.band->low_hz, high.pick.frequency_hz);
  EXPECT_EQ(s.band->high_hz, low.pick.frequency_hz);
  EXPECT_EQ(s.peak->low_hz, high.pick.peak_frequency_hz);
  EXPECT_EQ(s.peak->high_hz, low.pick.peak_frequency_hz);
}

// band_electrical_at on a made-up curve: linear between the points either side (0.25 of the way
// from 40200 to 40100 Hz), phases along the shorter arc across +-180 deg, the power factor P/S of
// the interpolated powers (not a mix of the points' ratios), a grid point's own figures on it,
// none outside the curve or next to a point without a reading; band_interpolation_at's bracket.
TEST(OperatingBand, ElectricalFiguresAtAFrequencyAreInterpolatedBetweenTheCurvePoints) {
  BandRow row;
  auto point = [&row](double frequency_hz, double current_a, double phase_deg, double power_w, double apparent_va,
                      bool valid) {
    row.curve.push_back(CurveSample{frequency_hz, 0.0, true});
    SteadyStateResult r;
    r.electrical.valid = valid;
    r.electrical.rms_current_a_a = current_a;
    r.electrical.motional_phase_a_deg = phase_deg;
    r.electrical.power_a_w = power_w;
    r.electrical.apparent_power_a_va = apparent_va;
    r.electrical.power_factor_a = power_w / apparent_va;
    row.points.push_back(r);
  };
  point(40200.0, 0.4, 170.0, 2.0, 20.0, true);
  point(40100.0, 0.8, -170.0, 6.0, 40.0, true);
  point(40000.0, 1.0, -160.0, 7.0, 50.0, false);
  const std::optional<ElectricalReadings> mid = band_electrical_at(row, 40175.0);
  ASSERT_TRUE(mid.has_value());
  EXPECT_DOUBLE_EQ(mid->rms_current_a_a, 0.5);
  EXPECT_NEAR(mid->motional_phase_a_deg, 175.0, 1e-9);
  EXPECT_DOUBLE_EQ(mid->power_a_w, 3.0);
  EXPECT_DOUBLE_EQ(mid->apparent_power_a_va, 25.0);
  EXPECT_DOUBLE_EQ(mid->power_factor_a, 3.0 / 25.0);  // a mix of the ratios would be 0.1125
  EXPECT_DOUBLE_EQ(mid->power_factor_b, 0.0);         // no apparent power
  const std::optional<BandInterpolation> at = band_interpolation_at(row, 40175.0);
  ASSERT_TRUE(at.has_value());
  EXPECT_EQ(at->upper, 0U);
  EXPECT_EQ(at->lower, 1U);
  EXPECT_DOUBLE_EQ(at->weight, 0.25);
  const std::optional<BandInterpolation> on = band_interpolation_at(row, 40100.0);
  ASSERT_TRUE(on.has_value());
  EXPECT_EQ(on->upper, 1U);
  EXPECT_EQ(on->lower, 1U);
  EXPECT_EQ(on->weight, 0.0);
  EXPECT_FALSE(band_interpolation_at(row, 40300.0).has_value());
  EXPECT_FALSE(band_interpolation_at(row, 39900.0).has_value());
  EXPECT_DOUBLE_EQ(band_electrical_at(row, 40100.0)->rms_current_a_a, 0.8);
  EXPECT_FALSE(band_electrical_at(row, 40300.0).has_value());
  EXPECT_FALSE(band_electrical_at(row, 40050.0).has_value());
  EXPECT_FALSE(band_electrical_at(row, 39900.0).has_value());
}

TEST(OperatingBand, AWarmerStatorWhoseStiffnessFallsMovesThePeakDown) {
  const MotorModel model(li2019_softening_when_hot());
  const auto rows = operating_band(model, coarse_grid({400.0}, {0.0, 50.0}), test::two_thread_for, 2);
  const BandRow& cold = row_at(rows, 400.0, 0.0);
  const BandRow& hot = row_at(rows, 400.0, 50.0);
  ASSERT_TRUE(cold.pick.decided) << cold.pick.reason;
  ASSERT_TRUE(hot.pick.decided) << hot.pick.reason;
  // a_K = -5e-4 /K: about -10 Hz/K at 40 kHz (measured: ~450 Hz over 50 K at 400 V).
  EXPECT_GT(cold.pick.peak_frequency_hz - hot.pick.peak_frequency_hz, 200.0)
      << cold.pick.peak_frequency_hz << " vs " << hot.pick.peak_frequency_hz;
  EXPECT_GE(hot.pick.frequency_hz, hot.pick.peak_frequency_hz + 100.0);
  // The cold row is the motor without the effect: the frozen rise 0 changes nothing.
  const auto plain = operating_band(MotorModel(test::calibrated_parameters()), coarse_grid({400.0}),
                                    test::two_thread_for, 2);
  EXPECT_EQ(plain.front().pick.peak_frequency_hz, cold.pick.peak_frequency_hz);
}

// Nine chains fill more than one vector of lanes (8), so the band runs as two tasks, here on two
// threads at once: the rows are those of one thread.
TEST(OperatingBand, RowsDoNotDependOnTheThreads) {
  const MotorModel model(test::calibrated_parameters());
  BandGrid grid = coarse_grid({200.0, 300.0, 400.0});
  grid.loads_n = {0.0, 1.0, 0.5};
  const auto one = operating_band(model, grid, serial_for, 1);
  std::size_t points = 0;
  std::size_t tasks = 0;
  std::mutex m;
  const ParallelFor counted = [&](std::size_t count, const std::function<void(std::size_t)>& body) {
    tasks = count;
    test::two_thread_for(count, body);
  };
  const auto two = operating_band(model, grid, counted, 2, [&] {
    const std::lock_guard lock(m);
    ++points;
  });
  EXPECT_EQ(tasks, 2u);
  EXPECT_EQ(points, 9u * 36u);
  ASSERT_EQ(one.size(), 9u);
  ASSERT_EQ(two.size(), 9u);
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].amplitude_v, two[i].amplitude_v);
    EXPECT_EQ(one[i].load_n, two[i].load_n);
    EXPECT_EQ(one[i].pick.frequency_hz, two[i].pick.frequency_hz);
    EXPECT_EQ(one[i].pick.speed_mm_s, two[i].pick.speed_mm_s);
    EXPECT_EQ(one[i].pick.reason, two[i].pick.reason);
    ASSERT_EQ(one[i].curve.size(), two[i].curve.size());
    for (std::size_t k = 0; k < one[i].curve.size(); ++k)
      EXPECT_EQ(one[i].curve[k].speed_mm_s, two[i].curve[k].speed_mm_s);
  }
  EXPECT_EQ(one[0].amplitude_v, 200.0);
  EXPECT_EQ(one[1].load_n, 1.0);
  EXPECT_EQ(one[8].amplitude_v, 400.0);
}

TEST(OperatingBand, SummaryOfUndecidedRowsHasNoBand) {
  std::vector<BandRow> rows(2);
  rows[0].pick.reason = "sweep higher";
  rows[1].pick.reason = "too noisy";
  const BandSummary s = summarize_band(rows);
  EXPECT_EQ(s.decided, 0u);
  EXPECT_EQ(s.undecided, 2u);
  EXPECT_FALSE(s.band.has_value());
  EXPECT_FALSE(s.peak.has_value());
}

}  // namespace
}  // namespace swum
