// Steady-state curves the paper plots (Figs. 13-16): speed versus voltage, versus
// frequency and versus load, and the frequency of maximum speed. Each point is an
// independent run to steady state from rest (run_to_steady_state's procedure, the points in the
// SIMD lanes of a batch: steady_state_batch.h), so a curve is the branch reached from rest
// (what an experiment that switches the drive on at each point sees).
#pragma once

#include <vector>

#include "analysis/steady_state/steady_state.h"
#include "model/motor_model.h"

namespace swum {

struct CurvePoint {
  OperatingPoint point;
  SteadyStateResult result;
};

/// One run per point, results in the order of the points (computed together in lanes).
[[nodiscard]] std::vector<CurvePoint> run_points(const MotorModel& model, const std::vector<OperatingPoint>& points);

/// Evenly spaced values start, start+step, ..., stop (inclusive within step/1e6).
[[nodiscard]] std::vector<double> evenly_spaced(double start, double stop, double step);

struct SpeedPeak {
  double frequency_hz = 0.0;
  double speed_mm_s = 0.0;
  bool found = false;  // false when no point moved forward (all speeds <= 0 or diverged)
};

/// Frequency of maximum forward speed of the motor resonance at `amplitude_v`, found as the paper's
/// experiments find it (model_spec §8 E9-E10): approaching from above, walking the grid
/// stop:start:-step down until the speed collapses below half the best speed seen (the
/// softening resonance jumps down there), then refined on a grid of step/4 within one
/// coarse step either side. Lobes below the collapse (a second regime under the stator
/// resonance, not reported by the paper) are not part of that resonance and are ignored.
[[nodiscard]] SpeedPeak frequency_of_max_speed(const MotorModel& model, double amplitude_v, double start_hz,
                                               double stop_hz, double step_hz, double load_n = 0.0);

}  // namespace swum
