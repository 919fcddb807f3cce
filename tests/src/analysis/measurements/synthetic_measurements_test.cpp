// Synthetic measurements (src/analysis/measurements/synthetic_measurements.h) handed out row by row: `swum
// synth` writes each row as soon as it is final, so the rows given to the callback must be the
// result's rows, in its order, whatever order the predictions complete in.
#include "analysis/measurements/synthetic_measurements.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../discrepancy_test_support.h"
#include "../thread_pool_for.h"

namespace swum {
namespace {

Measurement at(double amplitude_v, double frequency_hz, double time_s, int sweep) {
  return test::measurement_at(amplitude_v, frequency_hz, time_s, sweep);
}

std::string text_of(const MeasurementSet& layout, const std::vector<Measurement>& rows) {
  std::string text = format_measurements_header(layout);
  for (const Measurement& m : rows) text += format_measurement_row(layout, m);
  return text;
}

TEST(SynthRows, RowsAreHandedOutInTheResultsOrderWhateverOrderTheyComplete) {
  MotorParameters parameters = test::calibrated_motor();
  // Two sweeps and the file not in session order (time_s): a row waits for the rows before it
  // in the file (noise) and in the session (sweep ids).
  const std::vector<Measurement> points{at(200, 40600, 2.0, 1), at(200, 40400, 2.5, 1), at(300, 40500, 0.0, 0),
                                        at(300, 40300, 0.5, 0), at(300, 40100, 1.0, 0), at(200, 40200, 3.0, 1)};
  SynthOptions options;
  options.repeats = 2;
  options.seed = 11;
  options.frequency_jitter_hz = 5.0;
  options.speed_floor_mm_s = 0.5;
  const MeasurementSet layout = synthesis_layout(points, options);
  for (const ParallelFor& parallel : {ParallelFor(serial_for), ParallelFor(test::two_thread_for)}) {
    std::vector<Measurement> handed_out;
    const MeasurementSet set = synthesize_measurements(parameters, points, options, parallel,
                                                       [&](const Measurement& row) { handed_out.push_back(row); });
    ASSERT_EQ(set.rows.size(), points.size() * 2);
    EXPECT_EQ(text_of(layout, handed_out), format_measurements_csv(set));
    EXPECT_EQ(format_measurements_csv(set),
              format_measurements_csv(synthesize_measurements(parameters, points, options, test::two_thread_for)));
  }
}

TEST(SynthRows, WhatTheCallbackThrowsStopsTheSynthesis) {
  const std::vector<Measurement> points{at(200, 40600, 0.0, 0), at(200, 40400, 0.5, 0), at(300, 40500, 1.0, 1)};
  int calls = 0;
  EXPECT_THROW((void)synthesize_measurements(test::calibrated_motor(), points, SynthOptions{}, serial_for,
                                             [&](const Measurement&) {
                                               ++calls;
                                               throw std::runtime_error("disk full");
                                             }),
               std::runtime_error);
  EXPECT_EQ(calls, 1) << "no row after the one that failed";
}

}  // namespace
}  // namespace swum
