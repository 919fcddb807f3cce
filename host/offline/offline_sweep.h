// The offline counterpart of the live sweep: the model's steady speed at every
// (voltage, load, frequency) point, each from rest (run_to_steady_state's procedure), or each
// (voltage, load) as one continuous down-sweep (down_sweep_chain, as a device sweeps and as the
// operating point's curves are taken), on all cores, the points of each worker in the SIMD lanes
// of a batch (steady_state_batch.h).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "model/motor_model.h"
#include "output/sweep_table.h"

namespace swum::host {

struct OfflineGrid {
  std::vector<double> voltages;
  std::vector<double> frequencies_hz;
  std::vector<double> loads_n{0.0};
  double phase_deg = 90.0;
  int jobs = 0;          // 0 = all cores
  bool progress = true;  // a progress bar on a terminal (off when the sweep is one of many)
  // true: each (voltage, load) is one continuous down-sweep at the cold motor (the operating
  // point's curve: swum pick --config, swum population); false: every point from rest.
  bool down_sweep = false;
};

// Throws std::invalid_argument naming the option (--amplitude-v, --frequency-hz, --load, --drive-phase-deg) of a
// value no sweep can use: voltages 0..10000 V, frequencies 1000..200000 Hz, |load| <= 1000 N,
// phase -180..180 deg, every value finite.
void check_grid(const OfflineGrid& grid);

// Rows in (voltage, load, frequency) order; failed points have ok = false and a status. With
// grid.down_sweep a row's point started from the state of the next higher frequency's.
std::vector<SweepRow> sweep_model(const MotorModel& model, const OfflineGrid& grid);

// The grid's points in that order, not yet computed.
std::vector<SweepRow> model_sweep_points(const OfflineGrid& grid);

// One point from rest (what every row of a model sweep is).
SweepRow run_model_point(const MotorModel& model, const SweepRow& at, double phase_deg);

// Called from the worker threads, concurrently, as soon as rows[i] is computed (points complete
// out of order). What it throws stops the sweep: no new point starts, and the exception is
// rethrown once the points under way are done (and reported).
using ModelPointDone = std::function<void(std::size_t i)>;

// Computes rows[first..] in place (rows from model_sweep_points; those before `first` are
// left alone: a resumed sweep has them already).
void sweep_model(const MotorModel& model, const OfflineGrid& grid, std::vector<SweepRow>& rows, std::size_t first,
                 const ModelPointDone& point_done);

}  // namespace swum::host
