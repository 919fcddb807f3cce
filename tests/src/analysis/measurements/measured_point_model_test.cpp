// Predictions of measured points (src/analysis/measurements/measured_point_model.h): the chains a session
// is predicted in, and the physical point of predicting a sweep the way it was taken.
#include "analysis/measurements/measured_point_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "../discrepancy_test_support.h"

namespace swum {
namespace {

using test::measurement_at;

TEST(PredictionChains, SweepsRunInSessionOrderAndSpotPointsAlone) {
  const std::vector<Measurement> points{measurement_at(100, 41000, 3, 1), measurement_at(200, 40000, 0, std::nullopt),
                                        measurement_at(100, 40500, 4, 1), measurement_at(300, 41000, 1, 0),
                                        measurement_at(100, 40900, 3.5, 1)};
  const auto chains = prediction_chains(points);
  ASSERT_EQ(chains.size(), 3u);
  EXPECT_EQ(chains[0], (std::vector<std::size_t>{1}));        // spot point at t = 0
  EXPECT_EQ(chains[1], (std::vector<std::size_t>{3}));        // sweep 0
  EXPECT_EQ(chains[2], (std::vector<std::size_t>{0, 4, 2}));  // sweep 1 by time
}

MotorParameters calibrated() { return test::calibrated_motor(); }

// A softening resonator swept down from above the peak stays on the large-amplitude branch
// past the frequency at which, started from rest, it lands on the small one: the same points
// give different speeds depending on how they were taken. (This is why the workflow predicts
// a sweep by continuation: docs/discrepancy.md.)
TEST(SweepContinuation, DownwardSweepHoldsTheUpperBranchBelowThePeak) {
  const MotorParameters p = calibrated();
  std::vector<Measurement> sweep, spot;
  double t = 0.0;
  for (double f = 40600.0; f >= 39000.0; f -= 100.0) {
    sweep.push_back(measurement_at(400, f, t, 0));
    spot.push_back(measurement_at(400, f, t, std::nullopt));
    t += 1.0;
  }
  const PredictionOptions options;
  const auto by_sweep = predict_points(std::span(&p, 1), sweep, options, serial_for)[0];
  const auto from_rest = predict_points(std::span(&p, 1), spot, options, serial_for)[0];
  double largest_gap_mm_s = 0.0;
  for (std::size_t i = 0; i < sweep.size(); ++i) {
    ASSERT_TRUE(by_sweep[i].ok && from_rest[i].ok);
    largest_gap_mm_s = std::max(largest_gap_mm_s,
                                std::abs(by_sweep[i].value(Quantity::speed) - from_rest[i].value(Quantity::speed)));
  }
  // Above the peak the two agree (one branch); somewhere below it they part by far more than
  // the 0.5 mm/s steady-state tolerance.
  EXPECT_NEAR(by_sweep[0].value(Quantity::speed), from_rest[0].value(Quantity::speed), 2.0);
  EXPECT_GT(largest_gap_mm_s, 50.0);
}

}  // namespace
}  // namespace swum
