// `swum track-report --run NAME=track.csv ... --band band.csv --vpp V`: how close tracking runs
// stayed to the best speed available at each moment (host/track/track_report.h; docs/host.md).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "commands/commands.h"
#include "formats/number_format.h"
#include "output/plot.h"
#include "track/track_report.h"

namespace swum::host {
namespace {

struct TrackReportOptions {
  std::vector<std::string> runs;  // NAME=FILE
  std::string band_path;
  double vpp = 0.0;
  double load_n = 0.0;
  double ambient_c = 20.0;
  double skip_s = 30.0;
  double block_s = 30.0;
  std::string plot_dir;
  bool json = false;
};

void write_plots(const std::vector<TrackSeries>& runs, const std::vector<TrackRunSummary>& summaries,
                 const BestSpeedCurve& best, const TrackReportOptions& o) {
  std::filesystem::create_directories(o.plot_dir);
  const std::filesystem::path dir(o.plot_dir);
  PlotSpec share{"Share of the best speed at the same margin (" + format_number(o.vpp) + " Vpp)",
                 "device time (s)",
                 "mean speed / best at that temperature",
                 {}};
  PlotSpec frequency{"Drive frequency (" + format_number(o.vpp) + " Vpp)", "device time (s)", "frequency (kHz)", {}};
  PlotSpec speed{
      "Mover speed (dashed: best at the same margin, each run's temperature)", "device time (s)", "speed (mm/s)", {}};
  PlotSpec temperature{"Stator temperature", "device time (s)", "temperature (degC)", {}};
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const TrackSeries& r = runs[k];
    PlotSeries s{r.name, {}, {}, true, true};
    for (const TrackBlock& b : summaries[k].blocks) {
      s.x.push_back(0.5 * (b.start_s + b.end_s));
      s.y.push_back(b.share);
    }
    share.series.push_back(s);
    std::vector<double> khz, reference;
    for (std::size_t i = 0; i < r.time_s.size(); ++i) {
      khz.push_back(r.frequency_hz[i] * 1e-3);
      reference.push_back(best.speed_at(r.stator_temperature_c[i] - o.ambient_c));
    }
    frequency.series.push_back({r.name, r.time_s, khz, true, false});
    speed.series.push_back({r.name, r.time_s, r.speed_mm_s, true, false});
    speed.series.push_back({"best (" + r.name + ")", r.time_s, reference, true, false, true});
    temperature.series.push_back({r.name, r.time_s, r.stator_temperature_c, true, false});
  }
  if (!runs.empty()) {
    const double t0 = runs.front().time_s.front(), t1 = runs.front().time_s.back();
    share.series.push_back({"90 %", {t0, t1}, {0.9, 0.9}, true, false, true});
  }
  write_png_plot(share, dir / "tracking_share.png");
  write_png_plot(frequency, dir / "tracking_frequency.png");
  write_png_plot(speed, dir / "tracking_speed.png");
  write_png_plot(temperature, dir / "tracking_temperature.png");
}

void run_report(const TrackReportOptions& o) {
  if (!(o.vpp > 0.0 && o.vpp <= 10000.0)) throw std::invalid_argument("--vpp: must be in (0, 10000]");
  // The NAME=FILE form of every --run before any file is read.
  std::vector<std::pair<std::string, std::string>> named;
  for (const std::string& spec : o.runs) {
    const std::size_t eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
      throw std::invalid_argument("--run: " + spec + ": expected NAME=FILE");
    named.emplace_back(spec.substr(0, eq), spec.substr(eq + 1));
  }
  const BestSpeedCurve best = read_band_csv(o.band_path, o.vpp, o.load_n);
  std::vector<TrackSeries> runs;
  std::vector<TrackRunSummary> summaries;
  for (const auto& [name, path] : named) {
    runs.push_back(read_track_csv(path, name));
    summaries.push_back(summarise_track(runs.back(), best, o.ambient_c, o.skip_s, o.block_s));
  }
  if (!o.plot_dir.empty()) write_plots(runs, summaries, best, o);
  if (o.json) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const TrackRunSummary& s : summaries) {
      nlohmann::ordered_json blocks = nlohmann::ordered_json::array();
      for (const TrackBlock& b : s.blocks) {
        blocks.push_back({{"start_s", b.start_s},
                          {"end_s", b.end_s},
                          {"mean_speed_mm_s", b.mean_speed_mm_s},
                          {"best_speed_mm_s", b.best_speed_mm_s},
                          {"mean_rise_k", b.mean_rise_k},
                          {"margin_hz", b.margin_hz},
                          {"share", b.share}});
      }
      out.push_back({{"run", s.name},
                     {"min_share", s.min_share},
                     {"final_share", s.final_share},
                     {"final_frequency_hz", s.final_frequency_hz},
                     {"final_margin_hz", s.final_margin_hz},
                     {"final_rise_k", s.final_rise_k},
                     {"max_rise_k", s.max_rise_k},
                     {"blocks", blocks}});
    }
    std::printf("%s\n", out.dump(2).c_str());
    return;
  }
  std::printf("run      min share  final share  final frequency (Hz)  final margin (Hz)  final rise (K)\n");
  for (const TrackRunSummary& s : summaries) {
    std::printf("%-8s %9.3f  %11.3f  %20.1f  %17.1f  %14.1f\n", s.name.c_str(), s.min_share, s.final_share,
                s.final_frequency_hz, s.final_margin_hz, s.final_rise_k);
  }
}

}  // namespace

void add_track_report_command(CLI::App& app) {
  auto o = std::make_shared<TrackReportOptions>();
  CLI::App* sub = app.add_subcommand(
      "track-report", "Compare swum track runs with the best speed at each moment's temperature (a swum band table)");
  sub->add_option("--run", o->runs, "NAME=track.csv (repeat for several runs)")->required();
  sub->add_option("--band", o->band_path, "swum band CSV over temperature rises (the reference)")->required();
  sub->add_option("--vpp", o->vpp, "the runs' drive amplitude: the band rows used")->required();
  sub->add_option("--load", o->load_n, "the band rows' load (N)")->capture_default_str();
  sub->add_option("--ambient-c", o->ambient_c, "ambient temperature of the runs (degC)")->capture_default_str();
  sub->add_option("--skip-s", o->skip_s, "leave out the start (acquisition)")->capture_default_str();
  sub->add_option("--block-s", o->block_s, "length of the averaging blocks")->capture_default_str();
  sub->add_option("--plots", o->plot_dir, "directory for tracking_share/frequency/speed/temperature.png");
  sub->add_flag("--json", o->json, "per run: shares, blocks, final values as JSON");
  sub->callback([o] { run_report(*o); });
}

}  // namespace swum::host
