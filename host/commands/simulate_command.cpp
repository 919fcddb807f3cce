// `swum simulate`: one operating point run to steady state, with an optional CSV trace.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "analysis/steady_state/steady_state.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "commands/config_option.h"
#include "offline/motor_config.h"
#include "output/reports/model/simulation_report.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

struct SimulateOptions {
  std::string config_path;
  std::string amplitude_v;
  std::string frequency_hz;
  std::string load_n = "0";
  std::string phase_deg = "90";
  std::string duration_s;
  std::string trace_path;
  bool whole_duration = false;
  bool json = false;
};

void run_simulate(const SimulateOptions& o) {
  OperatingPoint point;
  point.amplitude_v = parse_finite_number(o.amplitude_v, "--amplitude-v");
  point.frequency_hz = parse_finite_number(o.frequency_hz, "--frequency-hz");
  point.load_n = parse_finite_number(o.load_n, "--load");
  point.phase_deg = parse_finite_number(o.phase_deg, "--drive-phase-deg");
  if (point.amplitude_v < 0.0) throw std::invalid_argument("--amplitude-v: must be >= 0, got " + o.amplitude_v);
  if (point.frequency_hz < 1000.0 || point.frequency_hz > 200000.0) {
    throw std::invalid_argument("--frequency-hz: must be within 1000..200000 Hz, got " + o.frequency_hz);
  }
  if (std::abs(point.phase_deg) > 180.0) {
    throw std::invalid_argument("--drive-phase-deg: must be within -180..180 degrees, got " + o.phase_deg);
  }

  const MotorModel model(load_motor_parameters(o.config_path));
  SteadyStateOptions options;
  if (!o.duration_s.empty()) {
    // At most this long: stop as soon as two windows agree (the real-time factor below counts
    // the simulated time actually run).
    const double duration_s = parse_finite_number(o.duration_s, "--duration-s");
    if (duration_s <= 0.0 || duration_s > 10.0) {
      throw std::invalid_argument("--duration-s: must be within (0, 10] s, got " + o.duration_s);
    }
    options = steady_state_options_within(duration_s);
  }
  options.stop_when_settled = !o.whole_duration;
  std::string trace_csv;
  if (!o.trace_path.empty()) {
    trace_csv = simulation_trace_header();
    // About 48 samples per drive period resolves the tip ellipse.
    const double steps_per_cycle = 1.0 / (model.time_step_s() * point.frequency_hz);
    options.trace_every_steps = static_cast<std::uint64_t>(std::max(1.0, steps_per_cycle / 48.0));
    options.trace = [&trace_csv](const TraceSample& s) { append_simulation_trace_row(trace_csv, s); };
  }

  const auto wall_start = std::chrono::steady_clock::now();
  const SteadyStateResult r = run_to_steady_state(model, point, options);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  if (!o.trace_path.empty()) write_text_file_atomically(o.trace_path, trace_csv);
  if (r.diverged) {
    throw CommandError("simulation diverged at " + o.amplitude_v + " V, " + o.frequency_hz + " Hz: " + r.failure,
                       kExitDiverged);
  }
  std::fputs((o.json ? simulation_json(point, r, wall_s) : simulation_text(point, r, wall_s)).c_str(), stdout);
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* sub = app.add_subcommand("simulate", "Run one operating point to steady state");
  add_config_option(*sub, o->config_path, "motor parameter file (TOML)");
  sub->add_option("--amplitude-v", o->amplitude_v, "terminal voltage amplitude per phase (V, zero-to-peak)")
      ->required();
  sub->add_option("--frequency-hz", o->frequency_hz, "drive frequency (Hz)")->required();
  sub->add_option("--load", o->load_n, "external load force on the mover (N)")->capture_default_str();
  sub->add_option("--drive-phase-deg", o->phase_deg, "phase of B relative to A (deg); sign = direction")
      ->capture_default_str();
  sub->add_option("--duration-s", o->duration_s,
                  "run at most this long (s), stopping when two windows agree (default 0.1)");
  sub->add_option("--trace", o->trace_path, "write a CSV trace of the run");
  sub->add_flag("--whole-duration", o->whole_duration,
                "run all of --duration-s even once two windows agree (timing, slow transients); the result is the last "
                "window");
  sub->add_flag("--json", o->json, "print one JSON object");
  sub->callback([o] { run_simulate(*o); });
}

}  // namespace swum::host
