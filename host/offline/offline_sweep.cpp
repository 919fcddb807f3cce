#include "offline/offline_sweep.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "analysis/steady_state.h"
#include "offline/parallel_for.h"
#include "output/progress_bar.h"

namespace swum::host {

SweepRow run_model_point(const MotorModel& model, const SweepRow& at, double phase_deg) {
  SweepRow row = at;
  OperatingPoint point;
  point.vpp = at.vpp;
  point.frequency_hz = at.frequency_hz;
  point.load_n = at.load_n;
  point.phase_deg = phase_deg;
  const SteadyStateResult r = run_to_steady_state(model, point);
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
  return row;
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
  check(grid.voltages, 0.0, 10000.0, "--vpp", "0..10000 Vpp");
  check(grid.frequencies_hz, 1000.0, 200000.0, "--frequency", "1000..200000 Hz");
  check(grid.loads_n, -1000.0, 1000.0, "--load", "-1000..1000 N");
  check({grid.phase_deg}, -180.0, 180.0, "--phase", "-180..180 deg");
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
  ProgressBar progress("sweep", rows.size() - first);
  make_parallel_for(static_cast<unsigned>(std::max(grid.jobs, 0)))(rows.size() - first, [&](std::size_t k) {
    const std::size_t i = first + k;
    rows[i] = run_model_point(model, rows[i], grid.phase_deg);
    progress.advance();
    if (point_done) point_done(i);
  });
}

std::vector<SweepRow> sweep_model(const MotorModel& model, const OfflineGrid& grid) {
  std::vector<SweepRow> rows = model_sweep_points(grid);
  sweep_model(model, grid, rows, 0, {});
  return rows;
}

}  // namespace swum::host
