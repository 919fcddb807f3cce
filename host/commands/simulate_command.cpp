// `swum simulate`: one operating point run to steady state, with an optional CSV trace.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "analysis/steady_state/steady_state.h"
#include "commands/command_error.h"
#include "commands/commands.h"
#include "offline/motor_config.h"
#include "output/text_files.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

struct SimulateOptions {
  std::string config_path;
  std::string vpp;
  std::string frequency_hz;
  std::string load_n = "0";
  std::string phase_deg = "90";
  std::string duration_s;
  std::string trace_path;
  bool whole_duration = false;
  bool json = false;
};

void append_trace_row(std::string& csv, const TraceSample& s) {
  char line[320];
  std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g,%.9g,%.9g,%.6g,%.6g,%.6g,%.6g,%.9g,%.9g\n", s.time_s, s.q1_m,
                s.q1_dot_m_s, s.q2_m, s.q2_dot_m_s, s.tip_normal_um, s.tip_tangential_um, s.normal_force_n,
                s.friction_force_n, s.mover_position_m, s.mover_velocity_m_s);
  csv += line;
}

void run_simulate(const SimulateOptions& o) {
  OperatingPoint point;
  point.vpp = parse_finite_number(o.vpp, "--vpp");
  point.frequency_hz = parse_finite_number(o.frequency_hz, "--frequency");
  point.load_n = parse_finite_number(o.load_n, "--load");
  point.phase_deg = parse_finite_number(o.phase_deg, "--phase");
  if (point.vpp < 0.0) throw std::invalid_argument("--vpp: must be >= 0, got " + o.vpp);
  if (point.frequency_hz < 1000.0 || point.frequency_hz > 200000.0) {
    throw std::invalid_argument("--frequency: must be within 1000..200000 Hz, got " + o.frequency_hz);
  }
  if (std::abs(point.phase_deg) > 180.0) {
    throw std::invalid_argument("--phase: must be within -180..180 degrees, got " + o.phase_deg);
  }

  const MotorModel model(load_motor_parameters(o.config_path));
  SteadyStateOptions options;
  if (!o.duration_s.empty()) {
    // At most this long: stop as soon as two windows agree (the real-time factor below counts
    // the simulated time actually run).
    const double duration_s = parse_finite_number(o.duration_s, "--duration");
    if (duration_s <= 0.0 || duration_s > 10.0) {
      throw std::invalid_argument("--duration: must be within (0, 10] s, got " + o.duration_s);
    }
    options = steady_state_options_within(duration_s);
  }
  options.stop_when_settled = !o.whole_duration;
  std::string trace_csv;
  if (!o.trace_path.empty()) {
    trace_csv = "time_s,q1_m,q1_dot_m_s,q2_m,q2_dot_m_s,tip_normal_um,tip_tangential_um,"
                "normal_force_n,friction_force_n,mover_position_m,mover_velocity_m_s\n";
    // About 48 samples per drive period resolves the tip ellipse.
    const double steps_per_cycle = 1.0 / (model.time_step_s() * point.frequency_hz);
    options.trace_every_steps = static_cast<std::uint64_t>(std::max(1.0, steps_per_cycle / 48.0));
    options.trace = [&trace_csv](const TraceSample& s) { append_trace_row(trace_csv, s); };
  }

  const auto wall_start = std::chrono::steady_clock::now();
  const SteadyStateResult r = run_to_steady_state(model, point, options);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  if (!o.trace_path.empty()) write_text_file_atomically(o.trace_path, trace_csv);
  if (r.diverged) {
    throw CommandError("simulation diverged at " + o.vpp + " Vpp, " + o.frequency_hz + " Hz: " + r.failure,
                       kExitDiverged);
  }
  const double realtime_factor = wall_s > 0.0 ? r.sim_s / wall_s : 0.0;
  if (o.json) {
    nlohmann::ordered_json j;
    j["vpp"] = point.vpp;
    j["frequency_hz"] = point.frequency_hz;
    j["load_n"] = point.load_n;
    j["phase_deg"] = point.phase_deg;
    j["steady"] = r.ok;
    if (!r.ok) j["note"] = r.failure;
    j["speed_mm_s"] = r.speed_mm_s;
    j["tip_normal_um"] = r.tip_normal_um;
    j["tip_tangential_um"] = r.tip_tangential_um;
    j["contact_fraction"] = r.contact_fraction;
    j["mean_normal_force_n"] = r.mean_normal_force_n;
    j["mean_friction_force_n"] = r.mean_friction_force_n;
    j["sim_s"] = r.sim_s;
    j["steps"] = r.steps;
    j["wall_s"] = wall_s;
    j["realtime_factor"] = realtime_factor;
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("operating point : %g Vpp, %g Hz, load %g N, phase %g deg\n", point.vpp, point.frequency_hz, point.load_n,
              point.phase_deg);
  if (!r.ok) std::printf("note            : not settled (%s)\n", r.failure.c_str());
  std::printf("mover speed     : %.3f mm/s\n", r.speed_mm_s);
  std::printf("tip amplitudes  : normal %.4f um, tangential %.4f um\n", r.tip_normal_um, r.tip_tangential_um);
  std::printf("contact fraction: %.3f\n", r.contact_fraction);
  std::printf("simulated       : %.4f s in %.3f s wall (%.1fx real time)\n", r.sim_s, wall_s, realtime_factor);
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* sub = app.add_subcommand("simulate", "Run one operating point to steady state");
  sub->add_option("--config", o->config_path, "motor parameter file (TOML)")->required();
  sub->add_option("--vpp", o->vpp, "drive voltage (V peak-to-peak)")->required();
  sub->add_option("--frequency", o->frequency_hz, "drive frequency (Hz)")->required();
  sub->add_option("--load", o->load_n, "external load force on the mover (N)")->capture_default_str();
  sub->add_option("--phase", o->phase_deg, "phase of B relative to A (deg); sign = direction")->capture_default_str();
  sub->add_option("--duration", o->duration_s,
                  "run at most this long (s), stopping when two windows agree (default 0.1)");
  sub->add_option("--trace", o->trace_path, "write a CSV trace of the run");
  sub->add_flag("--whole-duration", o->whole_duration,
                "run all of --duration even once two windows agree (timing, slow transients); the result is the last "
                "window");
  sub->add_flag("--json", o->json, "print one JSON object");
  sub->callback([o] { run_simulate(*o); });
}

}  // namespace swum::host
