// `swum sweep`: steady speed over voltages x frequencies x loads, either from the model
// (--config, all cores) or measured on a live device (--modbus / --can / --canopen, docs/host.md).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands/command_error.h"
#include "commands/commands.h"
#include "device/device_options.h"
#include "device/device_sweep.h"
#include "device/stop_signal.h"
#include "offline/motor_config.h"
#include "offline/offline_sweep.h"
#include "output/partial_file.h"
#include "output/progress_bar.h"
#include "output/sweep_resume.h"
#include "output/sweep_table.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

struct SweepOptions {
  std::string config_path;
  DeviceOptions device;
  double tick_hz = 10000.0;  // --tick-hz: lockstep (--canopen --sync-ticks)
  std::string amplitude_v_list;
  std::string frequency_range;
  std::string load_list = "0";
  double phase_deg = 90.0;
  int jobs = 0;
  double settle_ms = 50.0;
  double dwell_ms = 50.0;
  double amplitude_slew_v_per_s = 2000.0;
  std::string out_path;
  std::string plot_path;
  bool resume = false;
};

// The run stopped (Ctrl-C, device error, ...): its rows stay in OUT.partial, which --resume
// continues; a fresh run that wrote no row leaves nothing behind.
void keep_unfinished(const SweepOptions& o, PartialFile& file, std::size_t written, std::size_t new_rows,
                     std::size_t planned) {
  if (!o.resume && new_rows == 0) {
    try {
      file.discard();
    } catch (...) {
      // Nothing of value in it; the error being reported is the one that matters.
    }
    return;
  }
  std::fprintf(stderr, "swum: %zu of %zu points are in %s: the same command with --resume continues the sweep\n",
               written, planned, file.partial().c_str());
}

// The run completed: OUT.partial becomes OUT, then the plot and the failed points.
void finish(const SweepOptions& o, PartialFile& file, const std::vector<SweepRow>& rows, bool live) {
  file.commit();
  if (!o.plot_path.empty() && !rows.empty()) write_sweep_plot(rows, o.plot_path);
  const auto failed = std::count_if(rows.begin(), rows.end(), [](const SweepRow& r) { return !r.ok; });
  if (failed > 0) {
    throw CommandError(std::to_string(failed) + " of " + std::to_string(rows.size()) +
                           " points failed (status column of " + o.out_path + ")",
                       live ? kExitFailure : kExitDiverged);
  }
}

void run_model_sweep(const SweepOptions& o, const OfflineGrid& grid) {
  const std::string header = format_sweep_header(kModelSweep);
  std::vector<SweepRow> rows = model_sweep_points(grid);
  const MotorModel model(load_motor_parameters(o.config_path));
  SweepKept kept;
  if (o.resume) {
    kept = read_sweep_partial(o.out_path, header, rows);
    // Another --config or --drive-phase-deg gives other numbers at the same points: the last row, computed
    // again, must come out the same to the last digit.
    if (!kept.rows.empty()) {
      const std::size_t last = kept.rows.size() - 1;
      if (format_sweep_row(kModelSweep, run_model_point(model, rows[last], grid.phase_deg)) !=
          kept.lines[last + 1] + "\n") {
        throw CommandError("--resume: the last row of " + partial_path(o.out_path).string() +
                           " is not what this sweep computes at that point (other --config or --drive-phase-deg?)");
      }
    }
    std::copy(kept.rows.begin(), kept.rows.end(), rows.begin());
  } else {
    refuse_to_overwrite_sweep_partial(o.out_path);
  }
  const std::size_t first = kept.rows.size();
  PartialFile file = open_sweep_partial(o.out_path, header, kept, first);
  // Points complete out of order on the workers; the file gets them in grid order.
  InOrderRows writer(file, first);
  const StopSignal stop;
  try {
    sweep_model(model, grid, rows, first, [&](std::size_t i) {
      writer.complete(i, format_sweep_row(kModelSweep, rows[i]));
      // Ctrl-C: no new point starts; those under way finish and are written.
      if (StopSignal::requested() && writer.written() < rows.size()) {
        throw CommandError("interrupted", kExitInterrupted);
      }
    });
  } catch (...) {
    keep_unfinished(o, file, writer.written(), writer.written() - first, rows.size());
    throw;
  }
  finish(o, file, rows, false);
}

void run_device_sweep(const SweepOptions& o, const DeviceSweepPlan& plan) {
  check_plan(plan);  // before the device is touched or --out is written
  const std::string header = format_sweep_header(kDeviceSweep);
  const std::vector<SweepRow> planned = device_sweep_points(plan);
  SweepKept kept;
  DeviceSweepStart start;
  std::size_t keep = 0;
  if (o.resume) {
    kept = read_sweep_partial(o.out_path, header, planned);
    start = device_sweep_start(plan, kept.rows, keep);
    kept.rows.resize(keep);  // a curve cut short is measured again, from its top frequency
  } else {
    refuse_to_overwrite_sweep_partial(o.out_path);
  }
  if (o.resume && keep == planned.size()) {  // killed after its last point: nothing to measure
    PartialFile file = open_sweep_partial(o.out_path, header, kept, keep);
    finish(o, file, kept.rows, true);
    return;
  }
  const StopSignal stop;
  const auto device = o.device.open(o.tick_hz);
  PartialFile file = open_sweep_partial(o.out_path, header, kept, keep);
  ProgressBar progress("sweep " + device->name(), planned.size() - keep);
  std::vector<SweepRow> rows = kept.rows;
  std::size_t written = keep;
  try {
    sweep_device(
        *device, plan, rows,
        [&](const SweepRow& row) {
          file.append(format_sweep_row(kDeviceSweep, row));
          ++written;
          progress.advance();
        },
        start);
  } catch (...) {
    // Ctrl-C or a device error: the drive is already off; the rows measured are in the file.
    keep_unfinished(o, file, written, written - keep, planned.size());
    throw;
  }
  finish(o, file, rows, true);
}

void run_sweep(const SweepOptions& o) {
  OfflineGrid grid;
  grid.voltages = parse_number_list(o.amplitude_v_list, "--amplitude-v");
  grid.frequencies_hz = parse_range_or_value(o.frequency_range, "--frequency-hz");
  grid.loads_n = parse_number_list(o.load_list, "--load");
  grid.phase_deg = o.phase_deg;
  grid.jobs = o.jobs;
  check_grid(grid);
  if (o.jobs < 0) throw std::invalid_argument("--jobs: must be >= 1 (0 = all cores)");
  const bool live = !o.device.address.empty();
  if (live == !o.config_path.empty()) {
    throw std::invalid_argument("give either --config (model) or a device (--modbus / --can / --canopen)");
  }
  if (!live) {
    run_model_sweep(o, grid);
    return;
  }
  DeviceSweepPlan plan;
  plan.voltages = grid.voltages;
  plan.frequencies_hz = grid.frequencies_hz;
  plan.loads_n = grid.loads_n;
  plan.phase_deg = o.phase_deg;
  plan.settle_s = o.settle_ms * 1e-3;
  plan.dwell_s = o.dwell_ms * 1e-3;
  plan.amplitude_slew_v_per_s = o.amplitude_slew_v_per_s;
  run_device_sweep(o, plan);
}

}  // namespace

void add_sweep_command(CLI::App& app) {
  auto o = std::make_shared<SweepOptions>();
  CLI::App* sub = app.add_subcommand("sweep",
                                     "Steady speed over voltages x frequencies x loads (model or live device)");
  sub->add_option("--config", o->config_path, "motor parameter file (TOML): sweep the model offline");
  add_device_options(*sub, o->device, &o->tick_hz);
  sub->add_option("--amplitude-v", o->amplitude_v_list,
                  "terminal voltage amplitudes per phase, comma list (V, zero-to-peak)")
      ->required();
  sub->add_option("--frequency-hz", o->frequency_range, "START:STOP:STEP or one value (Hz); swept downward on a device")
      ->required();
  sub->add_option("--load", o->load_list, "loads, comma list (N)")->capture_default_str();
  sub->add_option("--drive-phase-deg", o->phase_deg, "phase of B ahead of A (deg)")->capture_default_str();
  sub->add_option("--jobs", o->jobs, "worker threads, model only (default: all cores)");
  sub->add_option("--settle-ms", o->settle_ms, "device: wait after each frequency step (device time, ms)")
      ->capture_default_str();
  sub->add_option("--dwell-ms", o->dwell_ms, "device: sampling window per point (device time, ms)")
      ->capture_default_str();
  sub->add_option("--amplitude-slew-v-per-s", o->amplitude_slew_v_per_s,
                  "device: amplitude slew limit for voltage ramps")
      ->capture_default_str();
  sub->add_option("--out", o->out_path,
                  "output CSV: speed, tip amplitudes and the electrical port per point (docs/host.md)")
      ->required();
  sub->add_option("--plot", o->plot_path, "output PNG plot");
  sub->add_flag("--resume", o->resume,
                "continue the unfinished sweep in OUT.partial (same options) instead of starting afresh");
  sub->callback([o] { run_sweep(*o); });
}

}  // namespace swum::host
