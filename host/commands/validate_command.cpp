// `swum validate`: the paper's facts (model_spec §8) on a motor config and its linear
// variant, as a markdown table plus the paper-style plots (Figs. 10-11, 13-16). This is
// what produces docs/validation.md's evidence; the same criteria run as tests in
// tests/validation.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "analysis/steady_state/operating_curves.h"
#include "analysis/studies/paper_facts.h"
#include "commands/commands.h"
#include "formats/number_format.h"
#include "offline/motor_config.h"
#include "output/plot.h"
#include "output/reports/validation_report.h"
#include "output/text_files.h"

namespace swum::host {
namespace {

namespace fs = std::filesystem;

struct ValidateOptions {
  std::string config_path;
  std::string literal_path;
  std::string out_dir;
};

PlotSeries speed_series(const std::string& label, const MotorModel& model, const std::vector<OperatingPoint>& points,
                        double (*x_of)(const OperatingPoint&)) {
  PlotSeries series{label, {}, {}};
  for (const CurvePoint& c : run_points(model, points)) {
    if (c.result.diverged) continue;
    series.x.push_back(x_of(c.point));
    series.y.push_back(c.result.speed_mm_s);
  }
  return series;
}

std::vector<OperatingPoint> grid(const std::vector<double>& vpps, const std::vector<double>& frequencies,
                                 const std::vector<double>& loads) {
  std::vector<OperatingPoint> points;
  for (double v : vpps)
    for (double f : frequencies)
      for (double l : loads) points.push_back({v, f, l, 90.0});
  return points;
}

void plot_speed_vs_voltage(const MotorModel& nl, const MotorModel& lin, const fs::path& path) {
  const auto points = grid(evenly_spaced(0, 400, 25), {40000}, {0});
  auto by_vpp = [](const OperatingPoint& p) { return p.vpp; };
  auto nl_future = std::async(std::launch::async, [&] { return speed_series("non-linear", nl, points, by_vpp); });
  PlotSeries linear = speed_series("linear", lin, points, by_vpp);
  write_png_plot({"No-load speed vs voltage at 40 kHz (paper Fig. 13)",
                  "drive voltage (Vpp)",
                  "mover speed (mm/s)",
                  {nl_future.get(), linear}},
                 path);
}

void plot_speed_vs_frequency(const MotorModel& nl, const MotorModel& lin, const fs::path& path) {
  auto by_khz = [](const OperatingPoint& p) { return p.frequency_hz / 1000.0; };
  PlotSpec spec{"No-load speed vs frequency (paper Fig. 14)", "drive frequency (kHz)", "mover speed (mm/s)", {}};
  std::vector<std::future<PlotSeries>> futures;
  for (double vpp : {100.0, 250.0, 400.0}) {
    const auto points = grid({vpp}, evenly_spaced(39000, 41000, 50), {0});
    futures.push_back(std::async(std::launch::async, [&nl, points, vpp, by_khz] {
      return speed_series(format_number(vpp, "%.0f") + " Vpp non-linear", nl, points, by_khz);
    }));
    PlotSeries linear = speed_series(format_number(vpp, "%.0f") + " Vpp linear", lin, points, by_khz);
    linear.draw_markers = false;
    spec.series.push_back(std::move(linear));
  }
  for (auto& f : futures) spec.series.push_back(f.get());
  write_png_plot(spec, path);
}

void plot_peak_frequency(PaperFacts& facts, const MotorModel& nl, const MotorModel& lin, const fs::path& path) {
  PlotSeries nl_series{"non-linear", {}, {}};
  PlotSeries lin_series{"linear", {}, {}};
  PlotSeries paper{"paper (Fig. 15 text)", {100, 250, 400}, {40.4, 40.2, 39.6}};
  paper.draw_line = false;
  for (double vpp : evenly_spaced(50, 400, 50)) {
    const SpeedPeak p = facts.peak(nl, vpp);
    if (p.found) {
      nl_series.x.push_back(vpp);
      nl_series.y.push_back(p.frequency_hz / 1000.0);
    }
    const SpeedPeak q = facts.peak(lin, vpp);
    if (q.found) {
      lin_series.x.push_back(vpp);
      lin_series.y.push_back(q.frequency_hz / 1000.0);
    }
  }
  write_png_plot({"Frequency of maximum no-load speed vs voltage (paper Fig. 15)",
                  "drive voltage (Vpp)",
                  "frequency of max speed (kHz)",
                  {nl_series, lin_series, paper}},
                 path);
}

void plot_speed_vs_load(const MotorModel& nl, const fs::path& path) {
  auto by_load = [](const OperatingPoint& p) { return p.load_n; };
  const std::vector<double> loads = evenly_spaced(0, 6, 0.5);
  PlotSpec spec{
      "Speed vs load at drift-aware and naive frequency (paper Fig. 16)", "load force (N)", "mover speed (mm/s)", {}};
  for (auto [vpp, f] : {std::pair{300.0, 40060.0}, {300.0, 40400.0}, {400.0, 39600.0}, {400.0, 40400.0}}) {
    spec.series.push_back(
        speed_series(format_number(vpp, "%.0f") + " Vpp at " + format_number(f / 1000, "%.2f") + " kHz", nl,
                     grid({vpp}, {f}, loads), by_load));
  }
  write_png_plot(spec, path);
}

// Free stator (mover removed: no preload, no contact), last drive period of a 30 ms run.
PlotSeries tip_ellipse(const MotorModel& free_stator, double vpp, double frequency_hz, const std::string& label) {
  SteadyStateOptions options;
  options.settle_s = 0.030;
  options.window_s = 1.0 / frequency_hz;
  options.max_s = options.settle_s + options.window_s;
  options.speed_tolerance_mm_s = 1e300;
  options.trace_every_steps = 1;
  PlotSeries series{label, {}, {}};
  series.draw_markers = false;
  const double from_s = options.settle_s;
  options.trace = [&series, from_s](const TraceSample& s) {
    if (s.time_s < from_s) return;
    series.x.push_back(s.tip_tangential_um);
    series.y.push_back(s.tip_normal_um);
  };
  (void)run_to_steady_state(free_stator, {vpp, frequency_hz, 0.0, 90.0}, options);
  return series;
}

void plot_tip_trajectories(const MotorParameters& parameters, const fs::path& dir) {
  MotorParameters free = parameters;
  free.contact.preload_n = 0.0;
  free.contact.stiffness_n_m = 0.0;
  const MotorModel free_stator(free);
  PlotSpec by_voltage{"Free-stator tip trajectory at 39.5 kHz (paper Fig. 10)",
                      "tangential tip displacement (um)",
                      "normal tip displacement (um)",
                      {}};
  for (double vpp : {100.0, 200.0, 300.0, 400.0}) {
    by_voltage.series.push_back(tip_ellipse(free_stator, vpp, 39500, format_number(vpp, "%.0f") + " Vpp"));
  }
  write_png_plot(by_voltage, dir / "fig10_tip_trajectory_vs_voltage.png");
  PlotSpec by_frequency{"Free-stator tip trajectory at 400 Vpp (paper Fig. 11)",
                        "tangential tip displacement (um)",
                        "normal tip displacement (um)",
                        {}};
  for (double f : {39000.0, 39200.0, 39500.0}) {
    by_frequency.series.push_back(tip_ellipse(free_stator, 400, f, format_number(f / 1000, "%.1f") + " kHz"));
  }
  write_png_plot(by_frequency, dir / "fig11_tip_trajectory_vs_frequency.png");
}

void run_validate(const ValidateOptions& o) {
  const MotorParameters parameters = load_motor_parameters(o.config_path);
  const MotorModel nonlinear(parameters);
  const MotorModel linear(linearised(parameters));
  const fs::path dir = o.out_dir;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create " + dir.string() + ": " + ec.message());

  PaperFacts facts(nonlinear, linear);
  std::vector<FactResult> results = facts.all();
  if (!o.literal_path.empty()) {
    const MotorModel literal(load_motor_parameters(o.literal_path));
    results.push_back(literal_reading_cross_check(literal));
  }
  const std::string table = validation_facts_table(results);
  write_text_file_atomically(dir / "facts.md", validation_facts_markdown(o.config_path, table));
  std::fputs(table.c_str(), stdout);

  plot_speed_vs_voltage(nonlinear, linear, dir / "fig13_speed_vs_voltage.png");
  plot_speed_vs_frequency(nonlinear, linear, dir / "fig14_speed_vs_frequency.png");
  plot_peak_frequency(facts, nonlinear, linear, dir / "fig15_peak_frequency_vs_voltage.png");
  plot_speed_vs_load(nonlinear, dir / "fig16_speed_vs_load.png");
  plot_tip_trajectories(parameters, dir);
}

}  // namespace

void add_validate_command(CLI::App& app) {
  auto o = std::make_shared<ValidateOptions>();
  CLI::App* sub = app.add_subcommand("validate", "Check the paper's facts and draw the paper-style plots");
  sub->add_option("--config", o->config_path, "motor parameter file (TOML)")->required();
  sub->add_option("--literal", o->literal_path, "the paper-literal config, for the §9 cross-check");
  sub->add_option("--out", o->out_dir, "output folder (facts.md and PNG plots)")->required();
  sub->callback([o] { run_validate(*o); });
}

}  // namespace swum::host
