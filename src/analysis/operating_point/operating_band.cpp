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

std::optional<BandInterpolation> band_interpolation_at(const BandRow& row, double frequency_hz) {
  // curve[k] and points[k] are the same point, frequencies falling with k.
  for (std::size_t k = 0; k < row.curve.size() && k < row.points.size(); ++k) {
    const double f_k = row.curve[k].frequency_hz;
    if (f_k < frequency_hz) {
      if (k == 0) return std::nullopt;  // above the curve
      const double f_up = row.curve[k - 1].frequency_hz;
      return BandInterpolation{k - 1, k, (f_up - frequency_hz) / (f_up - f_k)};
    }
    if (f_k == frequency_hz) return BandInterpolation{k, k, 0.0};
  }
  return std::nullopt;  // below the curve
}

std::optional<ElectricalReadings> band_electrical_at(const BandRow& row, double frequency_hz) {
  const std::optional<BandInterpolation> at = band_interpolation_at(row, frequency_hz);
  if (!at) return std::nullopt;
  const ElectricalReadings& up = row.points[at->upper].electrical;
  const ElectricalReadings& down = row.points[at->lower].electrical;
  if (!up.valid || !down.valid) return std::nullopt;
  if (at->upper == at->lower) return up;
  const double w = at->weight;  // 0 at the upper point, 1 at the lower
  auto mix = [w](double a, double b) { return a + w * (b - a); };
  auto mix_deg = [w](double a, double b) { return wrap_phase_deg(a + w * wrap_phase_deg(b - a)); };
  ElectricalReadings r = up;
  r.current_a_a = mix(up.current_a_a, down.current_a_a);
  r.current_b_a = mix(up.current_b_a, down.current_b_a);
  r.phase_a_deg = mix_deg(up.phase_a_deg, down.phase_a_deg);
  r.phase_b_deg = mix_deg(up.phase_b_deg, down.phase_b_deg);
  r.motional_current_a_a = mix(up.motional_current_a_a, down.motional_current_a_a);
  r.motional_current_b_a = mix(up.motional_current_b_a, down.motional_current_b_a);
  r.motional_phase_a_deg = mix_deg(up.motional_phase_a_deg, down.motional_phase_a_deg);
  r.motional_phase_b_deg = mix_deg(up.motional_phase_b_deg, down.motional_phase_b_deg);
  r.power_a_w = mix(up.power_a_w, down.power_a_w);
  r.power_b_w = mix(up.power_b_w, down.power_b_w);
  r.rms_current_a_a = mix(up.rms_current_a_a, down.rms_current_a_a);
  r.rms_current_b_a = mix(up.rms_current_b_a, down.rms_current_b_a);
  r.peak_current_a_a = mix(up.peak_current_a_a, down.peak_current_a_a);
  r.peak_current_b_a = mix(up.peak_current_b_a, down.peak_current_b_a);
  r.voltage_a_v = mix(up.voltage_a_v, down.voltage_a_v);
  r.voltage_b_v = mix(up.voltage_b_v, down.voltage_b_v);
  r.apparent_power_a_va = mix(up.apparent_power_a_va, down.apparent_power_a_va);
  r.apparent_power_b_va = mix(up.apparent_power_b_va, down.apparent_power_b_va);
  // P/S of the figures above (electrical_readings' definition), not a mix of the points' ratios:
  // the readings stay consistent, and a row's power factor is the same in swum band and swum size.
  r.power_factor_a = r.apparent_power_a_va > 0.0 ? r.power_a_w / r.apparent_power_a_va : 0.0;
  r.power_factor_b = r.apparent_power_b_va > 0.0 ? r.power_b_w / r.apparent_power_b_va : 0.0;
  return r;
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
