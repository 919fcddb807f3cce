// `swum band`: the range of drive frequencies an amplifier's oscillator must cover (docs/host.md,
// "swum band"). For every (voltage, load, stator temperature rise) the model runs one continuous
// down-sweep, each point from the state the previous one left, the slow states frozen at that
// rise (an OperatingChain, steady_state_batch.h); pick_operating_point then chooses the
// frequency a margin above the softening peak on that curve. Pure: model and grid in, rows out;
// the chains run on this machine's cores (parallel_for.h), each core's chains in SIMD lanes.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "analysis/operating_point/operating_point.h"
#include "model/motor_model.h"

namespace swum::host {

struct BandGrid {
  std::vector<double> voltages;
  std::vector<double> loads_n{0.0};
  std::vector<double> temperature_rises_k{0.0};
  std::vector<double> frequencies_hz;  // any order: each chain runs them from the highest down
  double margin_hz = 100.0;            // PickOptions::min_margin_hz
  int jobs = 0;                        // worker threads, 0 = all cores
};

// One chain's curve and its pick.
struct BandRow {
  double vpp = 0.0;
  double load_n = 0.0;
  double temperature_rise_k = 0.0;
  std::vector<CurveSample> curve;  // the chain's points, highest frequency first (ok = false: diverged)
  PickResult pick;
};

// Throws std::invalid_argument naming the option (--vpp, --frequency, --load as check_grid;
// --temperature-rise-k 0..300 K; --margin-hz 0..10000 Hz; --jobs 0..1024) of a value no band can
// use.
void check_band_grid(const BandGrid& grid);

// A rise other than 0 needs the thermal effect: throws std::invalid_argument naming
// --temperature-rise-k and `parameters_source` (the file) when it is off.
void check_band_thermal(const BandGrid& grid, const MotorParameters& parameters, const std::string& parameters_source);

// Called on a worker thread (concurrently) each time a point of some chain is final.
using BandPointDone = std::function<void()>;

// Rows in (voltage, load, temperature rise) order, the order of the grid's lists. The result does
// not depend on `jobs` (nor on the SIMD lanes: steady_state_batch.h).
std::vector<BandRow> operating_band(const MotorModel& model, const BandGrid& grid,
                                    const BandPointDone& point_done = {});

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

}  // namespace swum::host
