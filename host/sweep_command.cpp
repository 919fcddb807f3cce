// `swum sweep`: the model's steady speed over a grid of voltages, frequencies and loads,
// on all cores.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "analysis/steady_state.h"
#include "command_error.h"
#include "commands.h"
#include "motor_config.h"
#include "progress_bar.h"
#include "sweep_table.h"
#include "text_files.h"
#include "value_lists.h"

namespace swum::host {
namespace {

struct SweepOptions {
  std::string config_path;
  std::string vpp_list;
  std::string frequency_range;
  std::string load_list = "0";
  int jobs = 0;
  std::string out_path;
  std::string plot_path;
};

SweepRow run_point(const MotorModel& model, double vpp, double frequency_hz, double load_n) {
  SweepRow row;
  row.vpp = vpp;
  row.frequency_hz = frequency_hz;
  row.load_n = load_n;
  OperatingPoint point;
  point.vpp = vpp;
  point.frequency_hz = frequency_hz;
  point.load_n = load_n;
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

void run_sweep(const SweepOptions& o) {
  const std::vector<double> voltages = parse_number_list(o.vpp_list, "--vpp");
  const std::vector<double> frequencies = parse_range_or_value(o.frequency_range, "--frequency");
  const std::vector<double> loads = parse_number_list(o.load_list, "--load");
  for (double v : voltages) {
    if (v < 0.0) throw std::invalid_argument("--vpp: voltages must be >= 0");
  }
  for (double f : frequencies) {
    if (f < 1000.0 || f > 200000.0) throw std::invalid_argument("--frequency: must be within 1000..200000 Hz");
  }
  if (o.jobs < 0) throw std::invalid_argument("--jobs: must be >= 1 (0 = all cores)");

  const MotorModel model(load_motor_parameters(o.config_path));

  std::vector<SweepRow> rows;
  for (double v : voltages) {
    for (double load : loads) {
      for (double f : frequencies) rows.push_back(SweepRow{v, f, load});
    }
  }

  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const unsigned jobs = std::min<unsigned>(o.jobs > 0 ? static_cast<unsigned>(o.jobs) : cores,
                                           static_cast<unsigned>(rows.size()));
  ProgressBar progress("sweep", rows.size());
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i = next++; i < rows.size(); i = next++) {
      rows[i] = run_point(model, rows[i].vpp, rows[i].frequency_hz, rows[i].load_n);
      progress.advance();
    }
  };
  std::vector<std::thread> threads;
  for (unsigned t = 1; t < jobs; ++t) threads.emplace_back(worker);
  worker();
  for (auto& thread : threads) thread.join();

  write_text_file_atomically(o.out_path, format_sweep_csv(rows));
  if (!o.plot_path.empty()) write_sweep_plot(rows, o.plot_path);

  const auto failed = std::count_if(rows.begin(), rows.end(), [](const SweepRow& r) { return !r.ok; });
  if (failed > 0) {
    throw CommandError(std::to_string(failed) + " of " + std::to_string(rows.size()) +
                           " points diverged (status column of " + o.out_path + ")",
                       kExitDiverged);
  }
}

}  // namespace

void add_sweep_command(CLI::App& app) {
  auto o = std::make_shared<SweepOptions>();
  CLI::App* sub = app.add_subcommand("sweep", "Steady speed over voltages x frequencies x loads");
  sub->add_option("--config", o->config_path, "motor parameter file (TOML)")->required();
  sub->add_option("--vpp", o->vpp_list, "drive voltages, comma list (V peak-to-peak)")->required();
  sub->add_option("--frequency", o->frequency_range, "START:STOP:STEP or one value (Hz)")->required();
  sub->add_option("--load", o->load_list, "loads, comma list (N)")->capture_default_str();
  sub->add_option("--jobs", o->jobs, "worker threads (default: all cores)");
  sub->add_option("--out", o->out_path, "output CSV")->required();
  sub->add_option("--plot", o->plot_path, "output PNG plot");
  sub->callback([o] { run_sweep(*o); });
}

}  // namespace swum::host
