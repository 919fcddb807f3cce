#include "app/emu_options.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <tuple>

#include "app/milliseconds.h"
#include "can_codec.h"
#include "installation.h"

namespace swum::emu {

namespace {

// Option spellings swum-emu no longer accepts (issue 34, "One name per idea"): old, new (empty:
// removed), why. Not
// aliases: a command line holding one fails with one line naming the new spelling. swum's table is
// host/commands/retired_options.cpp; tests/host/cli_vocabulary.py checks both against --help.
struct RetiredEmuOption {
  const char* old_spelling;
  const char* new_spelling;
  const char* why;
};
constexpr RetiredEmuOption kRetiredEmuOptions[] = {
    {"--frequency", "--frequency-hz", "every frequency option carries its unit"},
    {"--phase", "--drive-phase-deg", "the drive phase (B ahead of A), named as in swum"},
    {"--duration", "--duration-s", "every duration option carries its unit"},
    {"--frequency-min", "--min-frequency-hz", "frequency bounds named alike in swum and swum-emu"},
    {"--frequency-max", "--max-frequency-hz", "frequency bounds named alike in swum and swum-emu"},
    {"--load-max", "--max-load-n", "limits named max-QUANTITY-UNIT"},
    {"--frequency-slew", "--frequency-slew-hz-per-s", "every slew limit carries its unit"},
    {"--encoder-max-rate", "--encoder-max-rate-hz", "every rate carries its unit"},
    {"--amplitude-max", "--max-amplitude-v",
     "a voltage is the terminal amplitude, in V; limits named max-QUANTITY-UNIT"},
    {"--amplitude-slew", "--amplitude-slew-v-per-s",
     "a voltage is the terminal amplitude; every slew limit carries its unit"},
};

// "--old was renamed --new (why)" ("--old was removed (why)") for the first retired spelling in
// argv (alone or as --old=V).
std::string retired_emu_option(int argc, const char* const* argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    for (const RetiredEmuOption& r : kRetiredEmuOptions) {
      const std::string_view old = r.old_spelling;
      if (arg == old || (arg.starts_with(old) && arg.size() > old.size() && arg[old.size()] == '='))
        return std::string(old) +
               (*r.new_spelling == '\0' ? std::string(" was removed") : std::string(" was renamed ") + r.new_spelling) +
               " (" + r.why + ")";
    }
  }
  return {};
}

}  // namespace

EmuOptions parse_emu_options(int argc, const char* const* argv) {
  EmuOptions o;
  CLI::App app{"swum-emu: two-phase ultrasonic-motor amplifier + motor emulator (docs/emulator.md)"};
  // Modbus connection limits: taken as text and parsed whole below (one-line errors).
  std::string modbus_idle_text = std::to_string(o.modbus_idle_timeout_ms);
  std::string modbus_frame_text = std::to_string(o.modbus_frame_timeout_ms);
  std::string modbus_evict_text = std::to_string(o.modbus_evict_idle_ms);
  app.set_version_flag("--version", installation::version_line("swum-emu"));
  app.add_option("--config", o.config_path,
                 "motor parameter file (TOML); default: li2019.toml of the data directory, the calibrated motor "
                 "(docs/install.md)")
      ->check(CLI::ExistingFile);
  app.add_option("--can", o.can_interface, "SocketCAN interface (e.g. vcan0); CAN off when absent");
  app.add_option("--node", o.can_node, "CAN node id")
      ->check(CLI::Range(int{protocol::can::kMinNode}, int{protocol::can::kMaxNode}));
  app.add_option("--can-profile", o.can_profile,
                 "with --can: the frames the node speaks: swum (docs/protocols.md) or cia402 (CANopen CiA 301/402, "
                 "docs/canopen.md)")
      ->check(CLI::IsMember({"swum", "cia402"}))
      ->capture_default_str();
  app.add_option("--modbus", o.modbus_spec, "tcp://HOST:PORT (port 0: any free port), rtu:/dev/TTY:BAUD, or none")
      ->capture_default_str();
  app.add_option("--modbus-unit", o.modbus_unit, "Modbus RTU unit id")->check(CLI::Range(1, 247));
  app.add_option("--modbus-idle-timeout-ms", modbus_idle_text,
                 "Modbus TCP: close a connection without a request for this long (0 = never)")
      ->type_name("MS")
      ->capture_default_str();
  app.add_option("--modbus-frame-timeout-ms", modbus_frame_text,
                 "Modbus: a request must be complete this long after its first byte (RTU: plus a 256-byte "
                 "frame's time on the line); TCP: its reply taken within as long again")
      ->type_name("MS")
      ->capture_default_str();
  app.add_option("--modbus-evict-idle-ms", modbus_evict_text,
                 "Modbus TCP: when all 16 slots are taken, the longest-idle holder idle at least this long "
                 "is closed to make room (0 = any idle holder)")
      ->type_name("MS")
      ->capture_default_str();
  app.add_option("--gpio", o.gpio_spec, "CHIP:enable=N,fault=M[,a=K,b=L] (GPIO off when absent)");
  app.add_option("--encoder-resolution-um", o.encoder_resolution_um, "encoder: mover travel per count")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--encoder-max-rate-hz", o.encoder_max_rate_hz, "encoder: max edges per second (Hz)")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  app.add_option("--tick-hz", o.tick_hz, "loop rate (Hz)")->check(CLI::Range(100.0, 100000.0))->capture_default_str();
  app.add_option("--duration-s", o.duration_s, "stop after this many emulated seconds (s; 0: run until SIGINT/SIGTERM)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--speedup", o.speedup, "run K times faster than wall time; 0 = as fast as possible")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--watchdog-ms", o.watchdog_ms, "command timeout while enabled (emulated ms; 0 = off)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--telemetry-hz", o.telemetry_hz, "CAN telemetry rate (Hz; 0 = off)")
      ->check(CLI::Range(0.0, 2000.0))
      ->capture_default_str();
  app.add_option("--heartbeat-ms", o.heartbeat_ms, "CAN heartbeat period (ms; 0 = off)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--min-frequency-hz", o.frequency_min_hz, "lowest accepted frequency setpoint (Hz)")
      ->capture_default_str();
  app.add_option("--max-frequency-hz", o.frequency_max_hz, "highest accepted frequency setpoint (Hz)")
      ->capture_default_str();
  app.add_option("--max-amplitude-v", o.max_amplitude_v,
                 "highest accepted amplitude setpoint: terminal voltage amplitude per phase (V, zero-to-peak)")
      ->capture_default_str();
  app.add_option("--max-load-n", o.load_max_n, "largest accepted |load force| (N)")->capture_default_str();
  app.add_option("--frequency-slew-hz-per-s", o.frequency_slew_hz_per_s, "frequency slew limit (Hz/s; 0 = none)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--amplitude-slew-v-per-s", o.amplitude_slew_v_per_s, "amplitude slew limit (V/s; 0 = none)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--frequency-hz", o.frequency_hz, "initial frequency setpoint (Hz)")->capture_default_str();
  app.add_option("--drive-phase-deg", o.phase_deg, "initial drive phase setpoint, B ahead of A (deg)")
      ->capture_default_str();
  app.add_option("--http", o.http_spec,
                 "HOST:PORT: serve the control API and the live dashboard there (port 0: any free port; "
                 "docs/http-api.md); off when absent");
  app.add_option("--http-token", o.http_token, "with --http: every API request must carry this token");
  app.add_option("--http-token-file", o.http_token_file, "with --http: the token is this file's first line")
      ->check(CLI::ExistingFile);
  app.add_option("--http-stream-hz", o.http_stream_hz, "with --http: telemetry stream rate without ?rate_hz=")
      ->check(CLI::Range(0.1, 100.0))
      ->capture_default_str();
  app.add_option("--http-stream-clients", o.http_stream_clients, "with --http: most telemetry streams at once")
      ->check(CLI::Range(1, 32))
      ->capture_default_str();
  app.add_option("--http-max-body-bytes", o.http_max_body_bytes, "with --http: larger request bodies get 413")
      ->check(CLI::Range(64, 1 << 20))
      ->capture_default_str();
  app.add_option("--http-recording-dir", o.http_recording_dir,
                 "with --http: where recordings are written (default: $TMPDIR or /tmp)")
      ->check(CLI::ExistingDirectory);
  app.add_flag("--rt", o.realtime, "try SCHED_FIFO + mlockall (a message, not a failure, when not permitted)");
  app.add_option("--cpu", o.cpu, "pin the real-time loop to this CPU (transports stay unpinned)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--spin-us", o.spin_us,
                 "sleep until this long before each tick, then busy-wait (lower wake-up latency, busier CPU)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  app.add_option("--ready-fd", o.ready_fd, "also write the ready line to this file descriptor");
  std::string clock = "internal";
  app.add_option("--clock", clock,
                 "internal: run on wall time (--speedup); external: lockstep, time advances only when a "
                 "controller steps it (Modbus advance register)")
      ->check(CLI::IsMember({"internal", "external"}))
      ->capture_default_str();
  app.add_option("--sync-ticks", o.sync_ticks, "lockstep over CAN: ticks per SYNC frame (one control cycle)")
      ->check(CLI::Range(1, 65535))
      ->capture_default_str();
  app.add_option("--scenario", o.scenario_path,
                 "timeline of loads and faults in emulated seconds (TOML, docs/scenarios.md)")
      ->check(CLI::ExistingFile);
  app.add_option("--inject", o.injections, "one event NAME@SECONDS[:key=value,...] (repeatable; docs/scenarios.md)")
      ->allow_extra_args(false);
  app.add_option("--record-can", o.record_can_path,
                 "with --can: every CAN frame received and sent, in candump's log format (canplayer replays it)");
  app.add_option("--record", o.record_path,
                 "write every applied command with its tick and every tick's telemetry to this CSV trace");
  app.add_option("--replay", o.replay_path,
                 "feed a recorded trace's commands at their ticks (no transports) and check the telemetry is "
                 "identical; exit 3 at the first difference")
      ->check(CLI::ExistingFile);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (std::string retired = retired_emu_option(argc, argv);
        !retired.empty() && !dynamic_cast<const CLI::Success*>(&e))
      throw EmuOptionError(retired);
    std::ostringstream out;
    std::ostringstream err;
    const int exit_code = app.exit(e, out, err);
    throw EmuCliExit(exit_code, out.str(), err.str());
  }
  if (o.config_path.empty()) {  // the installed calibrated motor; the ready line says so
    o.config_path = installation::default_config_path().string();
    o.config_is_default = true;
  }
  o.external_clock = clock == "external";
  if (!o.replay_path.empty() && !o.record_path.empty())
    throw EmuOptionError("--replay and --record: a replay records nothing (it compares with its trace)");
  if (!o.replay_path.empty()) {  // a replay opens no interface and runs on no clock
    for (const char* option : {"--modbus",
                               "--modbus-unit",
                               "--modbus-idle-timeout-ms",
                               "--modbus-frame-timeout-ms",
                               "--modbus-evict-idle-ms",
                               "--can",
                               "--node",
                               "--can-profile",
                               "--gpio",
                               "--encoder-resolution-um",
                               "--encoder-max-rate-hz",
                               "--telemetry-hz",
                               "--heartbeat-ms",
                               "--sync-ticks",
                               "--clock",
                               "--duration-s",
                               "--speedup",
                               "--spin-us",
                               "--rt",
                               "--cpu",
                               "--ready-fd",
                               "--record-can",
                               "--http"}) {
      if (app.count(option) > 0)
        throw EmuOptionError(std::string(option) +
                             " has no effect with --replay (a replay opens no interface and runs on no clock)");
    }
  }
  if (!o.record_can_path.empty() && o.can_interface.empty()) throw EmuOptionError("--record-can: only with --can");
  if (app.count("--can-profile") > 0 && o.can_interface.empty()) throw EmuOptionError("--can-profile: only with --can");
  o.heartbeat_given = app.count("--heartbeat-ms") > 0;
  if (o.can_profile == "cia402" && o.heartbeat_given && o.heartbeat_ms > 65535.0)
    throw EmuOptionError("--heartbeat-ms: at most 65535 with --can-profile cia402 (0x1017 is UNSIGNED16 ms)");
  if (app.count("--http") > 0 && o.http_spec.empty())
    throw EmuOptionError("--http: empty (expected HOST:PORT, e.g. 127.0.0.1:8080)");
  for (const char* option : {"--http-token", "--http-token-file", "--http-stream-hz", "--http-stream-clients",
                             "--http-max-body-bytes", "--http-recording-dir"}) {
    if (o.http_spec.empty() && app.count(option) > 0) throw EmuOptionError(std::string(option) + ": only with --http");
  }
  if (app.count("--http-token") > 0 && app.count("--http-token-file") > 0)
    throw EmuOptionError("--http-token and --http-token-file: give one");
  if (app.count("--http-token") > 0 && o.http_token.empty()) throw EmuOptionError("--http-token: empty");
  if (app.count("--sync-ticks") > 0 && (!o.external_clock || o.can_interface.empty()))
    throw EmuOptionError("--sync-ticks: only with --clock external and --can (ticks per CAN SYNC)");
  for (const char* wall_option : {"--speedup", "--spin-us"}) {
    if (o.external_clock && app.count(wall_option) > 0)
      throw EmuOptionError(std::string(wall_option) +
                           " paces wall time; with --clock external time advances only when the controller steps it");
  }
  for (const auto& [option, text, min_ms, value] :
       {std::tuple{"--modbus-idle-timeout-ms", &modbus_idle_text, 0, &o.modbus_idle_timeout_ms},
        std::tuple{"--modbus-frame-timeout-ms", &modbus_frame_text, 1, &o.modbus_frame_timeout_ms},
        std::tuple{"--modbus-evict-idle-ms", &modbus_evict_text, 0, &o.modbus_evict_idle_ms}}) {
    if (const std::string e = parse_milliseconds(*text, min_ms, kMaxTimeoutMs, *value); !e.empty())
      throw EmuOptionError(std::string(option) + ": " + e);
  }
  return o;
}

AmplifierConfig amplifier_config(const EmuOptions& o) {
  if (o.frequency_min_hz > o.frequency_max_hz) throw EmuOptionError("--min-frequency-hz is above --max-frequency-hz");
  AmplifierConfig amp;
  amp.limits.min_frequency_hz = o.frequency_min_hz;
  amp.limits.max_frequency_hz = o.frequency_max_hz;
  amp.limits.max_amplitude_v = o.max_amplitude_v;
  amp.limits.max_abs_load_n = o.load_max_n;
  amp.frequency_slew_hz_per_s = o.frequency_slew_hz_per_s;
  amp.amplitude_slew_v_per_s = o.amplitude_slew_v_per_s;
  amp.frequency_hz = o.frequency_hz;
  amp.phase_deg = o.phase_deg;
  amp.watchdog_s = o.watchdog_ms * 1e-3;
  // A default slew above the largest a command may ask for raises that limit.
  amp.limits.max_frequency_slew_hz_per_s = std::max(amp.limits.max_frequency_slew_hz_per_s,
                                                    amp.frequency_slew_hz_per_s);
  amp.limits.max_amplitude_slew_v_per_s = std::max(amp.limits.max_amplitude_slew_v_per_s, amp.amplitude_slew_v_per_s);
  Command initial;
  initial.fields = Command::kFrequency | Command::kPhase;
  initial.frequency_hz = amp.frequency_hz;
  initial.phase_deg = amp.phase_deg;
  if (validate(initial, amp.limits) != Reason::none)
    throw EmuOptionError("initial --frequency-hz / --drive-phase-deg outside the accepted limits");
  return amp;
}

std::optional<ModbusEndpoint> modbus_endpoint(const EmuOptions& o) {
  if (o.modbus_spec == "none") return std::nullopt;
  ModbusEndpoint endpoint;
  if (const std::string e = parse_modbus_endpoint(o.modbus_spec, endpoint); !e.empty())
    throw EmuOptionError("--modbus: " + e);
  return endpoint;
}

ModbusTcpOptions modbus_tcp_options(const EmuOptions& o) {
  ModbusTcpOptions tcp;
  tcp.idle_timeout_ms = o.modbus_idle_timeout_ms;
  tcp.frame_timeout_ms = o.modbus_frame_timeout_ms;
  tcp.evict_idle_ms = o.modbus_evict_idle_ms;
  return tcp;
}

CanopenProfileConfig canopen_profile_config(const EmuOptions& o, const AmplifierLimits& limits) {
  CanopenProfileConfig c;
  c.node = static_cast<std::uint8_t>(o.can_node);
  c.limits = limits;
  c.heartbeat_ms = o.heartbeat_given ? static_cast<int>(std::lround(o.heartbeat_ms)) : -1;
  return c;
}

CanTransportConfig can_transport_config(const EmuOptions& o) {
  CanTransportConfig can;
  can.node = static_cast<std::uint8_t>(o.can_node);
  can.telemetry_hz = o.telemetry_hz;
  can.heartbeat_s = o.heartbeat_ms * 1e-3;
  can.sync_ticks = static_cast<std::uint32_t>(o.sync_ticks);
  return can;
}

GpioConfig gpio_config(const EmuOptions& o) {
  GpioConfig gpio;
  if (const std::string e = parse_gpio_spec(o.gpio_spec, gpio); !e.empty()) throw EmuOptionError("--gpio: " + e);
  gpio.encoder_resolution_m = o.encoder_resolution_um * 1e-6;
  gpio.max_edge_rate_hz = o.encoder_max_rate_hz;
  return gpio;
}

namespace {
std::uint64_t duration_ticks(const EmuOptions& o) {
  return o.duration_s > 0.0 ? static_cast<std::uint64_t>(std::llround(o.duration_s * o.tick_hz)) : 0;
}
}  // namespace

LoopConfig loop_config(const EmuOptions& o) {
  LoopConfig loop;
  loop.speedup = o.speedup;
  loop.realtime = o.realtime;
  loop.spin_s = o.spin_us * 1e-6;
  loop.stats_every_ticks = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(o.tick_hz / 10.0));
  loop.max_ticks = duration_ticks(o);
  return loop;
}

std::optional<HttpConfig> http_config(const EmuOptions& o) {
  if (o.http_spec.empty()) return std::nullopt;
  HttpConfig http;
  protocol::ModbusEndpoint endpoint;  // the same HOST:PORT grammar as --modbus tcp://
  if (o.http_spec.find("://") != std::string::npos ||
      !protocol::parse_modbus_endpoint("tcp://" + o.http_spec, endpoint).empty() || !endpoint.tcp ||
      endpoint.host.empty())
    throw EmuOptionError("--http '" + o.http_spec +
                         "': expected HOST:PORT (e.g. 127.0.0.1:8080; port 0: any free port)");
  http.host = endpoint.host;
  http.port = endpoint.port;
  http.token = o.http_token;
  if (!o.http_token_file.empty()) {
    std::ifstream in(o.http_token_file);
    if (!in || !std::getline(in, http.token))
      throw EmuOptionError("--http-token-file " + o.http_token_file + ": cannot read a first line");
    while (!http.token.empty() && (http.token.back() == '\r' || http.token.back() == ' ')) http.token.pop_back();
    if (http.token.empty())
      throw EmuOptionError("--http-token-file " + o.http_token_file + ": the first line is empty");
  }
  for (const char c : http.token) {
    if (static_cast<unsigned char>(c) <= ' ' || c == 0x7f)
      throw EmuOptionError("--http-token: spaces and control characters cannot be sent in a header");
  }
  http.stream_default_hz = o.http_stream_hz;
  http.max_stream_clients = o.http_stream_clients;
  http.max_body_bytes = static_cast<std::size_t>(o.http_max_body_bytes);
  http.recording_directory = o.http_recording_dir;
  if (http.recording_directory.empty()) {
    const char* tmp = std::getenv("TMPDIR");
    http.recording_directory = tmp != nullptr && *tmp != '\0' ? tmp : "/tmp";
  }
  http.trace_recording = !o.record_path.empty();
  return http;
}

LockstepConfig lockstep_config(const EmuOptions& o) {
  LockstepConfig lockstep;
  lockstep.max_ticks = duration_ticks(o);
  return lockstep;
}

}  // namespace swum::emu
