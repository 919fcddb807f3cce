#include "analysis/operating_point/operating_band.h"

#include <algorithm>
#include <functional>
#include <span>

#include "analysis/steady_state/steady_state.h"
#include "analysis/steady_state/steady_state_batch.h"
#include "model/simulation/batch_simulator.h"

namespace swum {
namespace {

// A point that blew up is a collapse for the pick, as in a model sweep (model_pick.h); an
// unsettled one is a measured speed.
CurveSample sample_of(const OperatingPoint& point, const SteadyStateResult& r) {
  CurveSample s;
  s.frequency_hz = point.frequency_hz;
  s.ok = !r.diverged;
  s.speed_mm_s = r.diverged ? 0.0 : r.speed_mm_s;
  return s;
}

void widen(std::optional<FrequencyRange>& range, double f) {
  if (!range) {
    range = FrequencyRange{f, f};
    return;
  }
  range->low_hz = std::min(range->low_hz, f);
  range->high_hz = std::max(range->high_hz, f);
}

}  // namespace

OperatingChain down_sweep_chain(std::vector<double> frequencies_hz, double amplitude_v, double load_n, double rise_k,
                                double phase_deg) {
  std::sort(frequencies_hz.begin(), frequencies_hz.end(), std::greater<>());
  OperatingChain chain;
  for (double f : frequencies_hz) {
    OperatingPoint point;
    point.amplitude_v = amplitude_v;
    point.frequency_hz = f;
    point.load_n = load_n;
    point.phase_deg = phase_deg;
    point.stator_temperature_rise_k = rise_k;
    point.freeze_slow_states = true;
    chain.push_back(point);
  }
  return chain;
}

std::vector<BandRow> operating_band(const MotorModel& model, const BandGrid& grid, const ParallelFor& parallel,
                                    std::size_t tasks, const BandPointDone& point_done) {
  std::vector<BandRow> rows;
  std::vector<OperatingChain> chains;
  for (double v : grid.voltages) {
    for (double load : grid.loads_n) {
      for (double rise : grid.temperature_rises_k) {
        rows.push_back(BandRow{v, load, rise, {}, {}, {}});
        chains.push_back(down_sweep_chain(grid.frequencies_hz, v, load, rise));
      }
    }
  }
  // As a model sweep runs its points (host/offline/offline_sweep.cpp): as many tasks as asked
  // while each still fills a vector of lanes, a contiguous run of chains per task; a chain stays
  // in one lane.
  const std::size_t batches = (chains.size() + BatchSimulator::kLanePadding - 1) / BatchSimulator::kLanePadding;
  tasks = std::clamp<std::size_t>(batches, 1, std::max<std::size_t>(tasks, 1));
  const std::size_t per_task = (chains.size() + tasks - 1) / tasks;
  parallel(tasks, [&](std::size_t task) {
    const std::size_t begin = std::min(chains.size(), task * per_task);
    const std::size_t end = std::min(chains.size(), begin + per_task);
    const std::span<const OperatingChain> mine(chains.data() + begin, end - begin);
    auto done = [&](std::size_t, std::size_t, const SteadyStateResult&) {
      if (point_done) point_done();
    };
    const auto results = run_chains_to_steady_state(model, mine, {}, kDefaultBatchLanes, done);
    for (std::size_t c = 0; c < mine.size(); ++c) {
      BandRow& row = rows[begin + c];
      for (std::size_t k = 0; k < mine[c].size(); ++k) row.curve.push_back(sample_of(mine[c][k], results[c][k]));
      row.points = results[c];
    }
  });
  PickOptions options;
  options.min_margin_hz = grid.margin_hz;
  for (BandRow& row : rows) row.pick = pick_operating_point(row.curve, options);
  return rows;
}

BandSummary summarize_band(const std::vector<BandRow>& rows) {
  BandSummary s;
  for (const BandRow& row : rows) {
    if (!row.pick.decided) {
      ++s.undecided;
      continue;
    }
    ++s.decided;
    widen(s.band, row.pick.frequency_hz);
    widen(s.peak, row.pick.peak_frequency_hz);
  }
  return s;
}

}  // namespace swum
