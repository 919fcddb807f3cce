// `swum pick (--sweep CSV | --config F | --modbus/--can DEVICE) --amplitude-v LIST [--load LIST]`: the
// operating frequency per voltage and load by pick_operating_point, from a sweep table, an
// offline model down-sweep (the curve swum band takes) or a live sweep of a device; optional
// schedule, JSON and plots (docs/host.md).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "analysis/operating_point/operating_point.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "device/device_options.h"
#include "device/device_sweep.h"
#include "device/stop_signal.h"
#include "offline/model_pick.h"
#include "offline/motor_config.h"
#include "offline/offline_sweep.h"
#include "output/progress_bar.h"
#include "output/reports/operating_point/pick_plots.h"
#include "output/reports/operating_point/pick_report.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

struct PickCommandOptions {
  std::string sweep_path;
  std::string config_path;
  DeviceOptions device;
  double tick_hz = 10000.0;  // --tick-hz: lockstep (--canopen --sync-ticks)
  std::string amplitude_v_list;
  std::string load_list = "0";
  double margin_hz = kDefaultMarginHz;
  bool json = false;
  std::string schedule_path;
  std::string plot_dir;
  std::string save_sweep_path;
  // Sources that measure (model or device).
  std::string frequency_range = kDefaultFrequencyGrid;
  std::string plot_loads = "0,0.5,1,1.5,2,2.5,3";
  double settle_ms = 50.0;
  double dwell_ms = 50.0;
  double amplitude_slew_v_per_s = 2000.0;
};

// The one place a measuring source is chosen: model (offline) or device (live).
class Source {
 public:
  explicit Source(const PickCommandOptions& o) : o_(o) {
    const int sources = !o.sweep_path.empty() + !o.config_path.empty() + !o.device.address.empty();
    if (sources != 1)
      throw std::invalid_argument(
          "give exactly one source: --sweep, --config or a device (--modbus / --can / --canopen)");
    if (!o.config_path.empty()) model_ = std::make_unique<MotorModel>(load_motor_parameters(o.config_path));
    if (!o.device.address.empty()) device_ = o.device.open(o.tick_hz);
  }
  bool measures() const { return model_ || device_; }
  std::string describe() const {
    if (model_) return "model " + o_.config_path;
    if (device_) return device_->name();
    return o_.sweep_path;
  }

  // Appends to `rows` as points are measured, so a Ctrl-C or device error keeps them.
  void measure(const std::vector<double>& voltages, const std::vector<double>& frequencies,
               const std::vector<double>& loads, std::vector<SweepRow>& rows) {
    if (model_) {
      // The operating point's curve: one continuous down-sweep per (voltage, load), as a device
      // sweeps and as swum band takes it (down_sweep_chain).
      OfflineGrid grid{voltages, frequencies, loads};
      grid.down_sweep = true;
      const auto measured = sweep_model(*model_, grid);
      rows.insert(rows.end(), measured.begin(), measured.end());
      return;
    }
    const DeviceSweepPlan p = plan(voltages, frequencies, loads);
    ProgressBar progress("sweep " + device_->name(), voltages.size() * frequencies.size() * loads.size());
    sweep_device(*device_, p, rows, [&](const SweepRow&) { progress.advance(); });
  }

  DeviceSweepPlan plan(const std::vector<double>& voltages, const std::vector<double>& frequencies,
                       const std::vector<double>& loads) const {
    return plan_for(o_, voltages, frequencies, loads);
  }
  static DeviceSweepPlan plan_for(const PickCommandOptions& o_, const std::vector<double>& voltages,
                                  const std::vector<double>& frequencies, const std::vector<double>& loads) {
    DeviceSweepPlan p;
    p.voltages = voltages;
    p.frequencies_hz = frequencies;
    p.loads_n = loads;
    p.settle_s = o_.settle_ms * 1e-3;
    p.dwell_s = o_.dwell_ms * 1e-3;
    p.amplitude_slew_v_per_s = o_.amplitude_slew_v_per_s;
    return p;
  }

 private:
  const PickCommandOptions& o_;
  std::unique_ptr<MotorModel> model_;
  std::unique_ptr<Device> device_;
};

std::vector<SweepRow> read_sweep(const std::string& path) {
  try {
    return parse_sweep_csv(read_text_file(path), path);
  } catch (const CommandError&) {
    throw;
  } catch (const std::exception& e) {
    throw CommandError(e.what());
  }
}

void report(const PickCommandOptions& o, const std::vector<VoltagePick>& picks) {
  std::fputs((o.json ? pick_json(picks) : pick_text(picks)).c_str(), stdout);
  if (!o.schedule_path.empty()) write_text_file_atomically(o.schedule_path, pick_schedule_csv(picks));
}

// The figures at the first --load (its picks only).
void write_plots(const PickCommandOptions& o, Source& source, const std::vector<SweepRow>& sweep,
                 const std::vector<VoltagePick>& all_picks, double load_n, const PickOptions& options) {
  std::vector<VoltagePick> picks;
  for (const VoltagePick& p : all_picks) {
    if (p.load_n == load_n) picks.push_back(p);
  }
  const std::filesystem::path dir(o.plot_dir);
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) throw CommandError("cannot create " + o.plot_dir + ": " + error.message());
  write_speed_vs_frequency_plot(sweep, picks, load_n, dir / "speed_vs_frequency.png");
  write_frequency_vs_voltage_plot(picks, options.naive_frequency_hz, dir / "frequency_vs_amplitude_v.png");
  // Fig. 16: speed vs load at the picked and the naive frequency; measured when the source
  // can measure, else taken from the table's rows at other loads (when it has them).
  std::vector<SweepRow> load_rows;
  if (source.measures()) {
    const std::vector<double> loads = parse_number_list(o.plot_loads, "--plot-loads");
    for (const auto& p : picks) {
      if (!p.result.decided) continue;
      source.measure({p.amplitude_v}, {options.naive_frequency_hz, p.result.frequency_hz}, loads, load_rows);
    }
  } else {
    load_rows = sweep;
  }
  std::set<double> loads;
  for (const SweepRow& r : load_rows) loads.insert(r.load_n);
  if (loads.size() < 2) {
    std::fprintf(stderr, "swum: speed_vs_load.png not written: the sweep table has one load only "
                         "(use --config or a device, or sweep several loads)\n");
    return;
  }
  write_speed_vs_load_plot(load_rows, picks, options.naive_frequency_hz, dir / "speed_vs_load.png");
}

void run_pick(const PickCommandOptions& o) {
  const std::vector<double> voltages = parse_number_list(o.amplitude_v_list, "--amplitude-v");
  const std::vector<double> loads = parse_number_list(o.load_list, "--load");
  if (!(o.margin_hz >= 0.0 && o.margin_hz <= 10000.0))
    throw std::invalid_argument("--margin-hz: must be within 0..10000");
  OfflineGrid grid{voltages, {40000.0}, loads};
  const bool measuring = o.sweep_path.empty();
  if (measuring) grid.frequencies_hz = parse_range_or_value(o.frequency_range, "--frequency-hz");
  check_grid(grid);  // every bad value named before a device or a file is touched
  if (measuring) check_plan(Source::plan_for(o, grid.voltages, grid.frequencies_hz, grid.loads_n));
  StopSignal stop;
  Source source(o);
  std::vector<SweepRow> sweep;
  if (source.measures()) {
    try {
      source.measure(voltages, grid.frequencies_hz, loads, sweep);
    } catch (...) {
      if (!o.save_sweep_path.empty() && !sweep.empty()) {
        write_text_file_atomically(o.save_sweep_path, format_sweep_csv(sweep));
        std::fprintf(stderr, "swum: %zu points measured before the stop were written to %s\n", sweep.size(),
                     o.save_sweep_path.c_str());
      }
      throw;
    }
    if (!o.save_sweep_path.empty()) write_text_file_atomically(o.save_sweep_path, format_sweep_csv(sweep));
  } else {
    sweep = read_sweep(o.sweep_path);
  }
  PickOptions options;
  options.min_margin_hz = o.margin_hz;
  const std::vector<VoltagePick> picks = pick_voltages(sweep, voltages, loads, options, source.describe());
  const bool any_undecided = std::any_of(picks.begin(), picks.end(),
                                         [](const VoltagePick& p) { return !p.result.decided; });
  report(o, picks);
  if (!o.plot_dir.empty()) write_plots(o, source, sweep, picks, loads.front(), options);
  if (any_undecided) throw CommandError("no frequency picked for some voltages (see reason)", kExitFailure);
}

}  // namespace

void add_pick_command(CLI::App& app) {
  auto o = std::make_shared<PickCommandOptions>();
  CLI::App* sub = app.add_subcommand("pick",
                                     "Operating frequency per voltage (from a sweep table, the model or a device)");
  sub->add_option("--sweep", o->sweep_path, "sweep CSV (swum sweep --out)");
  sub->add_option("--config", o->config_path, "motor parameter file: sweep the model offline first");
  add_device_options(*sub, o->device, &o->tick_hz);
  sub->add_option("--amplitude-v", o->amplitude_v_list,
                  "terminal voltage amplitudes per phase, comma list (V, zero-to-peak)")
      ->required();
  sub->add_option("--load", o->load_list,
                  "loads, comma list: the rows to use / to sweep at (N); a pick per voltage and load")
      ->capture_default_str();
  sub->add_option("--margin-hz", o->margin_hz, "minimum margin above the peak (Hz), as swum band")
      ->capture_default_str();
  sub->add_flag("--json", o->json, "JSON list on stdout");
  sub->add_option("--schedule", o->schedule_path, "write amplitude_v,load_n,frequency_hz CSV");
  sub->add_option("--plot-dir", o->plot_dir,
                  "write speed_vs_frequency.png, frequency_vs_amplitude_v.png, speed_vs_load.png here");
  sub->add_option(
         "--frequency-hz", o->frequency_range,
         "model/device: START:STOP:STEP, swept from STOP down to START per voltage and load (Hz), as swum band")
      ->capture_default_str();
  sub->add_option("--plot-loads", o->plot_loads, "model/device: loads for speed_vs_load.png (N)")
      ->capture_default_str();
  sub->add_option("--save-sweep", o->save_sweep_path, "model/device: also write the sweep CSV");
  sub->add_option("--settle-ms", o->settle_ms, "device: wait after each frequency step (device time, ms)")
      ->capture_default_str();
  sub->add_option("--dwell-ms", o->dwell_ms, "device: sampling window per point (device time, ms)")
      ->capture_default_str();
  sub->add_option("--amplitude-slew-v-per-s", o->amplitude_slew_v_per_s,
                  "device: amplitude slew limit for voltage ramps")
      ->capture_default_str();
  sub->callback([o] { run_pick(*o); });
}

}  // namespace swum::host
