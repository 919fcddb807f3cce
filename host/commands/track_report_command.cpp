// `swum track-report --run NAME=track.csv ... --band band.csv --amplitude-v V`: how close tracking runs
// stayed to the best speed available at each moment (host/track/track_report.h; docs/host.md).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "commands/commands.h"
#include "output/reports/device/tracking_report.h"
#include "track/track_report.h"

namespace swum::host {
namespace {

struct TrackReportOptions {
  std::vector<std::string> runs;  // NAME=FILE
  std::string band_path;
  double amplitude_v = 0.0;
  double load_n = 0.0;
  double ambient_c = 20.0;
  double skip_s = 30.0;
  double block_s = 30.0;
  std::string plot_dir;
  bool json = false;
};

void run_report(const TrackReportOptions& o) {
  if (!(o.amplitude_v > 0.0 && o.amplitude_v <= 10000.0))
    throw std::invalid_argument("--amplitude-v: must be in (0, 10000]");
  // The NAME=FILE form of every --run before any file is read.
  std::vector<std::pair<std::string, std::string>> named;
  for (const std::string& spec : o.runs) {
    const std::size_t eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
      throw std::invalid_argument("--run: " + spec + ": expected NAME=FILE");
    named.emplace_back(spec.substr(0, eq), spec.substr(eq + 1));
  }
  const BestSpeedCurve best = read_band_csv(o.band_path, o.amplitude_v, o.load_n);
  std::vector<TrackSeries> runs;
  std::vector<TrackRunSummary> summaries;
  for (const auto& [name, path] : named) {
    runs.push_back(read_track_csv(path, name));
    summaries.push_back(summarise_track(runs.back(), best, o.ambient_c, o.skip_s, o.block_s));
  }
  if (!o.plot_dir.empty()) {
    std::filesystem::create_directories(o.plot_dir);
    write_tracking_plots(o.plot_dir, runs, summaries, best, o.amplitude_v, o.ambient_c);
  }
  std::fputs((o.json ? tracking_json(summaries) : tracking_text(summaries)).c_str(), stdout);
}

}  // namespace

void add_track_report_command(CLI::App& app) {
  auto o = std::make_shared<TrackReportOptions>();
  CLI::App* sub = app.add_subcommand(
      "track-report", "Compare swum track runs with the best speed at each moment's temperature (a swum band table)");
  sub->add_option("--run", o->runs, "NAME=track.csv (repeat for several runs)")->required();
  sub->add_option("--band", o->band_path, "swum band CSV over temperature rises (the reference)")->required();
  sub->add_option("--amplitude-v", o->amplitude_v, "the runs' drive amplitude: the band rows used")->required();
  sub->add_option("--load", o->load_n, "the band rows' load (N)")->capture_default_str();
  sub->add_option("--ambient-c", o->ambient_c, "ambient temperature of the runs (degC)")->capture_default_str();
  sub->add_option("--skip-s", o->skip_s, "leave out the start (acquisition)")->capture_default_str();
  sub->add_option("--block-s", o->block_s, "length of the averaging blocks")->capture_default_str();
  sub->add_option("--plot-dir", o->plot_dir, "directory for tracking_share/frequency/speed/temperature.png");
  sub->add_flag("--json", o->json, "per run: shares, blocks, final values as JSON");
  sub->callback([o] { run_report(*o); });
}

}  // namespace swum::host
