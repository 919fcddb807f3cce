// `swum sweep`: steady speed over voltages x frequencies x loads, either from the model
// (--config, all cores) or measured on a live device (--modbus / --can, docs/host.md).
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
#include "output/progress_bar.h"
#include "output/sweep_table.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

struct SweepOptions {
  std::string config_path;
  DeviceOptions device;
  std::string vpp_list;
  std::string frequency_range;
  std::string load_list = "0";
  double phase_deg = 90.0;
  int jobs = 0;
  double settle_ms = 50.0;
  double dwell_ms = 50.0;
  double ramp_vpp_per_s = 2000.0;
  std::string out_path;
  std::string plot_path;
};

void write_outputs(const SweepOptions& o, const std::vector<SweepRow>& rows) {
  write_text_file_atomically(o.out_path, format_sweep_csv(rows));
  if (!o.plot_path.empty() && !rows.empty()) write_sweep_plot(rows, o.plot_path);
}

void run_sweep(const SweepOptions& o) {
  OfflineGrid grid;
  grid.voltages = parse_number_list(o.vpp_list, "--vpp");
  grid.frequencies_hz = parse_range_or_value(o.frequency_range, "--frequency");
  grid.loads_n = parse_number_list(o.load_list, "--load");
  grid.phase_deg = o.phase_deg;
  grid.jobs = o.jobs;
  check_grid(grid);
  if (o.jobs < 0) throw std::invalid_argument("--jobs: must be >= 1 (0 = all cores)");
  const bool live = !o.device.address.empty();
  if (live == !o.config_path.empty()) {
    throw std::invalid_argument("give either --config (model) or a device (--modbus / --can)");
  }

  std::vector<SweepRow> rows;
  if (!live) {
    rows = sweep_model(MotorModel(load_motor_parameters(o.config_path)), grid);
  } else {
    DeviceSweepPlan plan;
    plan.voltages = grid.voltages;
    plan.frequencies_hz = grid.frequencies_hz;
    plan.loads_n = grid.loads_n;
    plan.phase_deg = o.phase_deg;
    plan.settle_s = o.settle_ms * 1e-3;
    plan.dwell_s = o.dwell_ms * 1e-3;
    plan.ramp_vpp_per_s = o.ramp_vpp_per_s;
    check_plan(plan);  // before the device is touched or --out is written
    StopSignal stop;
    const auto device = open_device(o.device.address, o.device.timeouts());
    ProgressBar progress("sweep " + device->name(),
                         plan.voltages.size() * plan.frequencies_hz.size() * plan.loads_n.size());
    try {
      sweep_device(*device, plan, rows, [&](const SweepRow&) { progress.advance(); });
    } catch (...) {
      // Ctrl-C or a device error: keep what was measured (the drive is already off); an
      // existing --out is left alone when nothing was measured.
      if (!rows.empty()) {
        write_outputs(o, rows);
        std::fprintf(stderr, "swum: %zu points measured before the stop were written to %s\n", rows.size(),
                     o.out_path.c_str());
      }
      throw;
    }
  }
  write_outputs(o, rows);

  const auto failed = std::count_if(rows.begin(), rows.end(), [](const SweepRow& r) { return !r.ok; });
  if (failed > 0) {
    throw CommandError(std::to_string(failed) + " of " + std::to_string(rows.size()) +
                           " points failed (status column of " + o.out_path + ")",
                       live ? kExitFailure : kExitDiverged);
  }
}

}  // namespace

void add_sweep_command(CLI::App& app) {
  auto o = std::make_shared<SweepOptions>();
  CLI::App* sub = app.add_subcommand("sweep",
                                     "Steady speed over voltages x frequencies x loads (model or live device)");
  sub->add_option("--config", o->config_path, "motor parameter file (TOML): sweep the model offline");
  add_device_options(*sub, o->device);
  sub->add_option("--vpp", o->vpp_list, "drive voltages, comma list (V peak-to-peak)")->required();
  sub->add_option("--frequency", o->frequency_range, "START:STOP:STEP or one value (Hz); swept downward on a device")
      ->required();
  sub->add_option("--load", o->load_list, "loads, comma list (N)")->capture_default_str();
  sub->add_option("--phase", o->phase_deg, "phase of B ahead of A (deg)")->capture_default_str();
  sub->add_option("--jobs", o->jobs, "worker threads, model only (default: all cores)");
  sub->add_option("--settle-ms", o->settle_ms, "device: wait after each frequency step (device time, ms)")
      ->capture_default_str();
  sub->add_option("--dwell-ms", o->dwell_ms, "device: sampling window per point (device time, ms)")
      ->capture_default_str();
  sub->add_option("--ramp-vpp-per-s", o->ramp_vpp_per_s, "device: amplitude slew limit for voltage ramps")
      ->capture_default_str();
  sub->add_option("--out", o->out_path, "output CSV")->required();
  sub->add_option("--plot", o->plot_path, "output PNG plot");
  sub->callback([o] { run_sweep(*o); });
}

}  // namespace swum::host
