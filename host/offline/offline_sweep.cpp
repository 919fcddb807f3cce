#include "offline/offline_sweep.h"

#include <algorithm>
#include <atomic>
#include <span>
#include <stdexcept>
#include <string>

#include "analysis/operating_point/operating_band.h"
#include "analysis/steady_state/steady_state.h"
#include "analysis/steady_state/steady_state_batch.h"
#include "model/simulation/batch_simulator.h"
#include "offline/parallel_for.h"
#include "output/progress_bar.h"

namespace swum::host {

namespace {

OperatingPoint operating_point(const SweepRow& at, double phase_deg) {
  OperatingPoint point;
  point.amplitude_v = at.amplitude_v;
  point.frequency_hz = at.frequency_hz;
  point.load_n = at.load_n;
  point.phase_deg = phase_deg;
  return point;
}

SweepRow row_of(const SweepRow& at, const SteadyStateResult& r) {
  SweepRow row = at;
  if (r.diverged) {
    row.ok = false;
    row.status = "diverged";
    return row;
  }
  row.ok = true;
  row.status = r.ok ? "ok" : "unsettled";
  row.speed_mm_s = r.speed_mm_s;
  row.tip_normal_um = r.tip_normal_um;
  row.tip_tangential_um = r.tip_tangential_um;
  const ElectricalReadings& e = r.electrical;
  if (e.valid) {
    row.electrical = SweepElectrical{e.current_a_a,
                                     e.current_b_a,
                                     e.phase_a_deg,
                                     e.phase_b_deg,
                                     e.motional_phase_a_deg,
                                     e.motional_phase_b_deg,
                                     e.power_a_w + e.power_b_w};
    row.sizing = SweepSizing{e.rms_current_a_a,     e.rms_current_b_a,     e.peak_current_a_a, e.peak_current_b_a,
                             e.voltage_a_v,         e.voltage_b_v,         e.power_a_w,        e.power_b_w,
                             e.apparent_power_a_va, e.apparent_power_b_va, e.power_factor_a,   e.power_factor_b};
  }
  return row;
}

}  // namespace

SweepRow run_model_point(const MotorModel& model, const SweepRow& at, double phase_deg) {
  // The batch path with one point: the same bits as that point in any lane of a sweep.
  const OperatingPoint point = operating_point(at, phase_deg);
  return row_of(at, run_points_to_steady_state(model, std::span(&point, 1)).front());
}

void check_grid(const OfflineGrid& grid) {
  auto check = [](const std::vector<double>& values, double lo, double hi, const char* option, const char* range) {
    if (values.empty()) throw std::invalid_argument(std::string(option) + ": no values");
    for (double v : values) {
      if (!(v >= lo && v <= hi)) {
        throw std::invalid_argument(std::string(option) + ": " + std::to_string(v) + " is outside " + range);
      }
    }
  };
  check(grid.voltages, 0.0, 10000.0, "--amplitude-v", "0..10000 V");
  check(grid.frequencies_hz, 1000.0, 200000.0, "--frequency-hz", "1000..200000 Hz");
  check(grid.loads_n, -1000.0, 1000.0, "--load", "-1000..1000 N");
  check({grid.phase_deg}, -180.0, 180.0, "--drive-phase-deg", "-180..180 deg");
}

std::vector<SweepRow> model_sweep_points(const OfflineGrid& grid) {
  std::vector<SweepRow> rows;
  for (double v : grid.voltages) {
    for (double load : grid.loads_n) {
      for (double f : grid.frequencies_hz) rows.push_back(SweepRow{v, f, load});
    }
  }
  return rows;
}

void sweep_model(const MotorModel& model, const OfflineGrid& grid, std::vector<SweepRow>& rows, std::size_t first,
                 const ModelPointDone& point_done) {
  first = std::min(first, rows.size());
  const std::size_t count = rows.size() - first;
  ProgressBar progress("sweep", grid.progress ? count : 0);  // total 0: no bar
  // Points in SIMD lanes (steady_state_batch.h), one batch per worker: as many tasks as threads
  // while each still fills a vector of lanes, contiguous runs of rows (the file gets them in order).
  const unsigned jobs = static_cast<unsigned>(std::max(grid.jobs, 0));
  const std::size_t batches = (count + BatchSimulator::kLanePadding - 1) / BatchSimulator::kLanePadding;
  const std::size_t tasks = std::clamp<std::size_t>(batches, 1, parallel_threads(jobs));
  const std::size_t per_task = (count + tasks - 1) / tasks;
  // What point_done throws stops the sweep: every batch finishes the points under way in its
  // lanes (reported) and starts no new one (the others learn it at their next point, through a
  // private exception swallowed here); the caller's exception is rethrown.
  struct Stopped {};
  std::atomic<bool> stopping{false};
  make_parallel_for(jobs)(tasks, [&](std::size_t task) {
    const std::size_t begin = first + task * per_task;
    const std::size_t end = std::min(rows.size(), begin + per_task);
    std::vector<OperatingChain> chains;
    for (std::size_t i = begin; i < end; ++i) chains.push_back({operating_point(rows[i], grid.phase_deg)});
    auto done = [&](std::size_t chain, std::size_t, const SteadyStateResult& r) {
      const std::size_t i = begin + chain;
      rows[i] = row_of(rows[i], r);
      progress.advance();
      try {
        if (point_done) point_done(i);
      } catch (...) {
        stopping = true;
        throw;
      }
      if (stopping) throw Stopped{};
    };
    try {
      (void)run_chains_to_steady_state(model, chains, {}, kDefaultBatchLanes, done);
    } catch (const Stopped&) {
      // another batch failed; its exception is the one reported
    }
  });
}

namespace {

// Each (voltage, load) as one down-sweep chain (down_sweep_chain: the curve `swum band` takes at
// rise 0), the chains of a task in the SIMD lanes of a batch as operating_band runs them; the
// rows in grid order.
std::vector<SweepRow> sweep_model_down(const MotorModel& model, const OfflineGrid& grid) {
  std::vector<SweepRow> rows = model_sweep_points(grid);
  const std::size_t per_curve = grid.frequencies_hz.size();
  std::vector<std::size_t> order(per_curve);  // chain position -> index in the grid's frequencies
  for (std::size_t k = 0; k < per_curve; ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return grid.frequencies_hz[a] > grid.frequencies_hz[b]; });
  std::vector<OperatingChain> chains;
  for (double v : grid.voltages) {
    for (double load : grid.loads_n)
      chains.push_back(down_sweep_chain(grid.frequencies_hz, v, load, 0.0, grid.phase_deg));
  }
  ProgressBar progress("sweep", grid.progress ? rows.size() : 0);
  const unsigned jobs = static_cast<unsigned>(std::max(grid.jobs, 0));
  const std::size_t batches = (chains.size() + BatchSimulator::kLanePadding - 1) / BatchSimulator::kLanePadding;
  const std::size_t tasks = std::clamp<std::size_t>(batches, 1, parallel_threads(jobs));
  const std::size_t per_task = (chains.size() + tasks - 1) / tasks;
  make_parallel_for(jobs)(tasks, [&](std::size_t task) {
    const std::size_t begin = std::min(chains.size(), task * per_task);
    const std::size_t end = std::min(chains.size(), begin + per_task);
    const std::span<const OperatingChain> mine(chains.data() + begin, end - begin);
    auto done = [&](std::size_t chain, std::size_t k, const SteadyStateResult& r) {
      SweepRow& row = rows[(begin + chain) * per_curve + order[k]];
      row = row_of(row, r);
      progress.advance();
    };
    (void)run_chains_to_steady_state(model, mine, {}, kDefaultBatchLanes, done);
  });
  return rows;
}

}  // namespace

std::vector<SweepRow> sweep_model(const MotorModel& model, const OfflineGrid& grid) {
  if (grid.down_sweep) return sweep_model_down(model, grid);
  std::vector<SweepRow> rows = model_sweep_points(grid);
  sweep_model(model, grid, rows, 0, {});
  return rows;
}

}  // namespace swum::host
