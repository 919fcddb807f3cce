// `swum control`: the reference closed-loop speed controller (docs/host.md, "swum control"):
// amplitude PI at a fixed drive frequency on a live device, one CSV row per cycle, the
// documented fault reaction. Against swum-emu --clock external it steps the emulator cycle by
// cycle (lockstep), so a run is reproducible byte for byte.
#include <cstdio>
#include <memory>
#include <set>
#include <string>

#include "commands/command_error.h"
#include "commands/commands.h"
#include "control/speed_control.h"
#include "device/device_options.h"
#include "device/stop_signal.h"
#include "output/partial_file.h"
#include "output/reports/device/control_report.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

struct ControlOptions {
  DeviceOptions device;
  SpeedControlSettings settings;
  double cycle_ms = 1.0;
  std::string recover = "1";
  std::string out_path;
};

// --recover: comma-separated fault codes, or "none".
std::set<int> parse_fault_codes(const std::string& text) {
  std::set<int> codes;
  if (text == "none") return codes;
  for (const double v : parse_number_list(text, "--recover")) {
    if (v != static_cast<int>(v) || v < 1 || v > 255)
      throw std::invalid_argument("--recover: " + text + ": fault codes are whole numbers in 1..255 (or none)");
    codes.insert(static_cast<int>(v));
  }
  return codes;
}

void run_control(ControlOptions& o) {
  SpeedControlSettings& s = o.settings;
  s.cycle_s = o.cycle_ms * 1e-3;
  s.recoverable_faults = parse_fault_codes(o.recover);
  StopSignal stop;
  const auto device = o.device.open(s.tick_hz);
  PartialFile out(o.out_path, kSpeedControlCsvHeader);
  SpeedControlHooks hooks;
  hooks.on_row = [&out](const SpeedControlRow& row) { out.append(format_speed_control_row(row)); };
  hooks.on_event = [](const std::string& line) { std::fprintf(stderr, "swum control: %s\n", line.c_str()); };
  hooks.stop_requested = [] { return StopSignal::requested(); };
  if (!device->lockstep()) {
    std::fprintf(stderr, "swum control: %s runs on wall time: cycles follow the host clock, not reproducible\n",
                 device->name().c_str());
  }
  SpeedControlResult result;
  try {
    result = run_speed_control(*device, s, hooks);
  } catch (const DeviceError&) {
    std::fprintf(stderr, "swum: the rows before the error are in %s\n", out.partial().c_str());
    throw;
  }
  out.commit();
  std::fputs(control_run_summary(result, s, device->lockstep(), o.out_path).c_str(), stdout);
  if (result.stop_reason == "interrupted")
    throw CommandError("interrupted: drive off; " + o.out_path + " holds every cycle run", kExitInterrupted);
  if (!result.stop_reason.empty())
    throw CommandError("stopped on " + result.stop_reason + "; drive off; rows in " + o.out_path);
}

}  // namespace

void add_control_command(CLI::App& app) {
  auto o = std::make_shared<ControlOptions>();
  SpeedControlSettings& s = o->settings;
  s.gains.kp_v_per_mm_s = kDefaultKpVPerMmS;
  s.gains.ki_v_per_mm = kDefaultKiVPerMm;
  CLI::App* sub = app.add_subcommand(
      "control", "Closed-loop speed control of a live device (amplitude PI; lockstep with swum-emu --clock external)");
  add_device_options(*sub, o->device);
  sub->add_option("--speed-mm-s", s.target_mm_s, "target speed (mm/s); the sign is the direction")->required();
  sub->add_option("--frequency-hz", s.frequency_hz, "fixed drive frequency (Hz; e.g. the one `swum pick` chose)")
      ->capture_default_str();
  sub->add_option("--duration-s", s.duration_s, "run length (s; device time in lockstep)")->capture_default_str();
  sub->add_option("--cycle-ms", o->cycle_ms, "control cycle (ms)")->capture_default_str();
  sub->add_option("--tick-hz", s.tick_hz, "lockstep: the device's tick rate (checked against its clock)")
      ->capture_default_str();
  sub->add_option("--kp", s.gains.kp_v_per_mm_s, "proportional gain (V per mm/s)")->capture_default_str();
  sub->add_option("--ki", s.gains.ki_v_per_mm, "integral gain (V per mm/s per s)")->capture_default_str();
  sub->add_option("--max-amplitude-v", s.gains.max_amplitude_v, "limit of the terminal voltage amplitude (V)")
      ->capture_default_str();
  sub->add_option("--amplitude-slew-v-per-s", s.slew.amplitude_v_per_s,
                  "amplitude slew limit the device applies (V/s, 0 = none)")
      ->capture_default_str();
  sub->add_option("--recover", o->recover, "fault codes recovered by reset + re-enable (comma list or none)")
      ->capture_default_str();
  sub->add_option("--holdoff-cycles", s.holdoff_cycles, "drive-off cycles before a recovery")->capture_default_str();
  sub->add_option("--max-retries", s.max_retries, "recoveries allowed per run")->capture_default_str();
  sub->add_option("--out", o->out_path, "output CSV, one row per cycle")->required();
  sub->callback([o] { run_control(*o); });
}

}  // namespace swum::host
