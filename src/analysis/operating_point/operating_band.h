// The range of drive frequencies an amplifier's oscillator must cover (docs/host.md, "swum
// band"). For every (voltage, load, stator temperature rise) the model runs one continuous
// down-sweep, each point from the state the previous one left, the slow states frozen at that
// rise (an OperatingChain, steady_state_batch.h); pick_operating_point then chooses the
// frequency a margin above the softening peak on that curve. Pure: model and grid in, rows out;
// the chains run as the caller's ParallelFor runs tasks, each task's chains in SIMD lanes.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "analysis/operating_point/operating_point.h"
#include "analysis/steady_state/parallel_for.h"
#include "analysis/steady_state/steady_state_batch.h"
#include "model/motor_model.h"

namespace swum {

struct BandGrid {
  std::vector<double> voltages;
  std::vector<double> loads_n{0.0};
  std::vector<double> temperature_rises_k{0.0};
  std::vector<double> frequencies_hz;   // any order: each chain runs them from the highest down
  double margin_hz = kDefaultMarginHz;  // PickOptions::min_margin_hz
};

// How every model curve of the operating point is taken (`swum band`, `swum pick --config`,
// `swum population`), as a device sweep takes it and an operator approaches a softening
// resonance: one continuous down-sweep, the frequencies from the highest to the lowest, each
// point from the state the previous one left (the first from rest), the slow states frozen at
// `rise_k` over ambient (0: the cold motor).
OperatingChain down_sweep_chain(std::vector<double> frequencies_hz, double amplitude_v, double load_n,
                                double rise_k = 0.0, double phase_deg = 90.0);

// One chain's curve and its pick.
struct BandRow {
  double amplitude_v = 0.0;
  double load_n = 0.0;
  double temperature_rise_k = 0.0;
  std::vector<CurveSample> curve;  // the chain's points, highest frequency first (ok = false: diverged)
  // The full steady state of each curve point, parallel to `curve` (the electrical port, tip
  // amplitudes, powers), so a caller can read any figure at any point of the curve.
  std::vector<SteadyStateResult> points;
  PickResult pick;
};

// Where `frequency_hz` sits on a row's curve: the two points either side (indices into `curve` and
// `points`, `upper` the higher frequency) and the weight of the lower one, 0 at the upper point
// and 1 at the lower, for a figure interpolated linearly between them. On a grid point both
// indices are that point's and the weight 0. None when the frequency is outside the curve.
struct BandInterpolation {
  std::size_t upper = 0;
  std::size_t lower = 0;
  double weight = 0.0;
};
[[nodiscard]] std::optional<BandInterpolation> band_interpolation_at(const BandRow& row, double frequency_hz);

// The electrical port's figures of a row at `frequency_hz` (its pick), each interpolated linearly
// between the two curve points either side (band_interpolation_at), as the pick's speed is
// (phases along the shorter arc); the power factor is P/S of the interpolated powers, as at a
// grid point. A frequency on a grid point gives that point's. None when the frequency is outside
// the curve or a point either side has no valid reading (diverged, 0 V).
[[nodiscard]] std::optional<ElectricalReadings> band_electrical_at(const BandRow& row, double frequency_hz);

// Called (concurrently, from the ParallelFor's tasks) each time a point of some chain is final.
using BandPointDone = std::function<void()>;

// Rows in (voltage, load, temperature rise) order, the order of the grid's lists. The chains are
// cut into `tasks` contiguous runs (at most one per SIMD batch), run by `parallel`; the result
// depends neither on `tasks` nor on the lanes (steady_state_batch.h).
std::vector<BandRow> operating_band(const MotorModel& model, const BandGrid& grid, const ParallelFor& parallel,
                                    std::size_t tasks, const BandPointDone& point_done = {});

// What an oscillator must cover: the picked frequencies and the peaks over the decided rows.
struct FrequencyRange {
  double low_hz = 0.0;
  double high_hz = 0.0;
};
struct BandSummary {
  std::size_t decided = 0;
  std::size_t undecided = 0;
  std::optional<FrequencyRange> band;  // picked frequencies; none when no row is decided
  std::optional<FrequencyRange> peak;  // peak frequencies of the same rows
};
BandSummary summarize_band(const std::vector<BandRow>& rows);

}  // namespace swum
