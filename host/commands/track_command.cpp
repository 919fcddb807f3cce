// `swum track`: hold a live device's drive a margin above the drifting softening peak (docs/host.md,
// "swum track"), by the motional phase (what an amplifier board measures) or by the speed, or
// hold the cold pick (the baseline); one CSV row per cycle, plots of the run.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "analysis/operating_point/operating_point.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "device/device_options.h"
#include "device/stop_signal.h"
#include "output/partial_file.h"
#include "output/reports/device/track_run_report.h"
#include "track/track_run.h"

namespace swum::host {
namespace {

struct TrackOptions {
  DeviceOptions device;
  TrackRunSettings settings;
  std::string method = "phase";
  double phase_deg = 0.0;
  CLI::Option* phase_option = nullptr;  // given or not
  double cycle_ms = 20.0;
  std::string out_path;
  std::string plot_dir;
};

TrackMethod parse_method(const std::string& text) {
  if (text == "phase") return TrackMethod::phase;
  if (text == "speed") return TrackMethod::speed;
  if (text == "fixed") return TrackMethod::fixed;
  throw std::invalid_argument("--method: " + text + ": expected phase, speed or fixed");
}

void run_track_command(TrackOptions& o) {
  TrackRunSettings& s = o.settings;
  s.tracker.method = parse_method(o.method);
  if (o.phase_option->count() > 0) {
    if (s.tracker.method != TrackMethod::phase)
      throw std::invalid_argument("--motional-phase-deg: only with --method phase");
    s.tracker.phase_setpoint_deg = o.phase_deg;
  }
  s.cycle_s = o.cycle_ms * 1e-3;
  s.tracker.direction = s.drive_phase_deg < 0.0 ? -1.0 : 1.0;
  // Every option checked before the device is opened or a file created.
  const std::string problem = check(s);
  if (!problem.empty()) throw std::invalid_argument(problem);
  StopSignal stop;
  const auto device = o.device.open(s.tick_hz);
  PartialFile out(o.out_path, kTrackCsvHeader);
  TrackPlotSeries series;
  TrackRunHooks hooks;
  hooks.on_row = [&](const TrackRow& row) {
    out.append(format_track_row(row));
    series.add(row);
  };
  hooks.on_event = [](const std::string& line) { std::fprintf(stderr, "swum track: %s\n", line.c_str()); };
  hooks.stop_requested = [] { return StopSignal::requested(); };
  if (!device->lockstep()) {
    std::fprintf(stderr, "swum track: %s runs on wall time: cycles follow the host clock, not reproducible\n",
                 device->name().c_str());
  }
  TrackRunResult result;
  try {
    result = run_track(*device, s, hooks);
  } catch (...) {
    std::fprintf(stderr, "swum: drive off; the rows before the error are in %s\n", out.partial().c_str());
    throw;
  }
  out.commit();
  if (!o.plot_dir.empty() && !series.time_s.empty()) write_track_plots(series, o.plot_dir, o.method);
  std::fputs(track_run_summary(result, device->lockstep(), o.method, o.out_path).c_str(), stdout);
  if (result.stop_reason == "interrupted")
    throw CommandError("interrupted: drive off; " + o.out_path + " holds every cycle run", kExitInterrupted);
  if (!result.stop_reason.empty())
    throw CommandError("stopped: " + result.stop_reason + "; drive off; rows in " + o.out_path);
}

}  // namespace

void add_track_command(CLI::App& app) {
  auto o = std::make_shared<TrackOptions>();
  TrackSettings& t = o->settings.tracker;
  CLI::App* sub = app.add_subcommand(
      "track", "Hold a live device a margin above its drifting resonance (by motional phase or speed)");
  add_device_options(*sub, o->device);
  sub->add_option("--amplitude-v", o->settings.amplitude_v, "terminal voltage amplitude per phase (V, zero-to-peak)")
      ->required();
  sub->add_option("--duration-s", o->settings.duration_s, "run length (s; device time in lockstep)")
      ->capture_default_str();
  sub->add_option("--method", o->method, "phase (PLL on the motional phase), speed (search), fixed (cold pick held)")
      ->capture_default_str();
  t.margin_hz = kDefaultMarginHz;  // the operating point's default margin (operating_point.h), as swum pick and band
  sub->add_option("--margin-hz", t.margin_hz, "operating point above the speed peak (Hz)")->capture_default_str();
  o->phase_option = sub->add_option("--motional-phase-deg", o->phase_deg,
                                    "phase method: motional phase set-point (deg, -90..30); default: measured at "
                                    "peak + margin after one cold speed search");
  sub->add_option("--start-hz", t.start_hz, "the approach starts here, above the resonance")->capture_default_str();
  sub->add_option("--min-frequency-hz", t.min_hz, "never drive below (Hz)")->capture_default_str();
  sub->add_option("--max-frequency-hz", t.max_hz, "never drive above (Hz)")->capture_default_str();
  sub->add_option("--search-step-hz", t.search_step_hz, "frequency step of a speed search")->capture_default_str();
  sub->add_option("--probe-interval-s", t.probe_interval_s, "speed method: time between searches")
      ->capture_default_str();
  sub->add_option("--phase-gain-hz-per-deg", t.phase_gain_hz_per_deg,
                  "phase method: frequency step per degree of phase error per cycle (Hz/deg)")
      ->capture_default_str();
  sub->add_option("--recovery-hz", t.recovery_hz, "jump above the operating point after a collapse")
      ->capture_default_str();
  sub->add_option("--drive-phase-deg", o->settings.drive_phase_deg,
                  "V_B ahead of V_A; its sign is the direction (phase method: forward only)")
      ->capture_default_str();
  sub->add_option("--amplitude-slew-v-per-s", o->settings.slew.amplitude_v_per_s,
                  "amplitude slew limit written to the device (V/s, 0 = none)")
      ->capture_default_str();
  sub->add_option("--frequency-slew-hz-per-s", o->settings.slew.frequency_hz_per_s,
                  "frequency slew limit written to the device (Hz/s, 0 = none)")
      ->capture_default_str();
  sub->add_option("--max-collapses", o->settings.tracker.max_collapses,
                  "collapses allowed in one run; one more ends it with an error")
      ->capture_default_str();
  sub->add_option("--cycle-ms", o->cycle_ms, "control cycle (ms)")->capture_default_str();
  sub->add_option("--tick-hz", o->settings.tick_hz, "lockstep: the device's tick rate (checked against its clock)")
      ->capture_default_str();
  sub->add_option("--out", o->out_path, "output CSV, one row per cycle")->required();
  sub->add_option("--plot-dir", o->plot_dir, "directory for track_frequency/speed/temperature/phase.png");
  sub->callback([o] { run_track_command(*o); });
}

}  // namespace swum::host
