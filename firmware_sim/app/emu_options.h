// swum-emu's command line (docs/emulator.md, "Options"): every option in one struct, the CLI11
// parser that fills it, and the conversions into the parts' configurations. Nothing here opens a
// socket, a device or a thread, so tests call it directly.
//
// Errors are exceptions with one line of text (main prints "swum-emu: TEXT", exit status 1):
// parse_emu_options() throws for the values CLI11 does not check itself (--modbus-*-ms), the
// conversions for bad or conflicting values (--min/--max-frequency-hz, initial --frequency-hz/--drive-phase-deg,
// --modbus, --gpio). run_emulator() calls each conversion where it needs the part, after reading
// the --config file, so that with several mistakes the same one is reported first as before
// the split.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/amplifier.h"
#include "core/lockstep_clock.h"
#include "core/realtime_loop.h"
#include "http/http_api.h"
#include "transports/can_transport.h"
#include "transports/canopen_profile.h"
#include "transports/gpio_transport.h"
#include "transports/modbus_server.h"

namespace swum::emu {

// Each field is one option; defaults are the documented ones.
struct EmuOptions {
  std::string config_path;           // --config: motor parameter file (default: the data directory's li2019.toml)
  bool config_is_default = false;    // no --config: config_path is the default motor (said on the ready line)
  std::string can_interface;         // --can; empty: CAN off
  int can_node = 1;                  // --node
  std::string can_profile = "swum";  // --can-profile: swum (docs/protocols.md) or cia402 (docs/canopen.md)
  bool heartbeat_given = false;      // --heartbeat-ms given (cia402: overrides 0x1017 at boot)
  std::string modbus_spec = "tcp://127.0.0.1:1502";                   // --modbus: tcp://HOST:PORT, rtu:DEV:BAUD or none
  int modbus_unit = 1;                                                // --modbus-unit (RTU)
  int modbus_idle_timeout_ms = ModbusTcpOptions{}.idle_timeout_ms;    // --modbus-idle-timeout-ms
  int modbus_frame_timeout_ms = ModbusTcpOptions{}.frame_timeout_ms;  // --modbus-frame-timeout-ms
  int modbus_evict_idle_ms = ModbusTcpOptions{}.evict_idle_ms;        // --modbus-evict-idle-ms
  std::string gpio_spec;                                         // --gpio: CHIP:enable=N,fault=M[,a=K,b=L]; empty: off
  double encoder_resolution_um = 10.0;                           // --encoder-resolution-um
  double encoder_max_rate_hz = 20000.0;                          // --encoder-max-rate-hz
  double tick_hz = 10000.0;                                      // --tick-hz
  double duration_s = 0.0;                                       // --duration-s (emulated); 0: until SIGINT/SIGTERM
  double speedup = 1.0;                                          // --speedup (factor); 0: as fast as possible
  double spin_us = 0.0;                                          // --spin-us
  double watchdog_ms = 100.0;                                    // --watchdog-ms (emulated); 0: off
  double telemetry_hz = 100.0;                                   // --telemetry-hz (CAN); 0: off
  double heartbeat_ms = 1000.0;                                  // --heartbeat-ms (CAN); 0: off
  double frequency_min_hz = AmplifierLimits{}.min_frequency_hz;  // --min-frequency-hz
  double frequency_max_hz = AmplifierLimits{}.max_frequency_hz;  // --max-frequency-hz
  double max_amplitude_v = AmplifierLimits{}.max_amplitude_v;    // --max-amplitude-v
  double load_max_n = AmplifierLimits{}.max_abs_load_n;          // --max-load-n
  double frequency_slew_hz_per_s = AmplifierConfig{}.frequency_slew_hz_per_s;  // --frequency-slew-hz-per-s
  double amplitude_slew_v_per_s = AmplifierConfig{}.amplitude_slew_v_per_s;    // --amplitude-slew-v-per-s
  double frequency_hz = AmplifierConfig{}.frequency_hz;                        // --frequency-hz (initial)
  double phase_deg = AmplifierConfig{}.phase_deg;                              // --drive-phase-deg (initial)
  bool external_clock = false;          // --clock external: lockstep (time advances only when a controller steps it)
  int sync_ticks = 10;                  // --sync-ticks: ticks per CAN SYNC in lockstep
  std::string scenario_path;            // --scenario; empty: none
  std::vector<std::string> injections;  // --inject NAME@T[:k=v,...], repeatable
  std::string record_can_path;          // --record-can: CAN frames in candump's log format; empty: none
  std::string record_path;              // --record: trace of commands and per-tick telemetry; empty: none
  std::string replay_path;              // --replay: feed a trace's commands in lockstep and compare; empty: none
  std::string http_spec;                // --http HOST:PORT: control API and dashboard; empty: off
  std::string http_token;               // --http-token; empty: none
  std::string http_token_file;          // --http-token-file: the token is this file's first line
  double http_stream_hz = HttpConfig{}.stream_default_hz;                   // --http-stream-hz: rate without ?rate_hz=
  int http_stream_clients = HttpConfig{}.max_stream_clients;                // --http-stream-clients
  int http_max_body_bytes = static_cast<int>(HttpConfig{}.max_body_bytes);  // --http-max-body-bytes
  std::string http_recording_dir;  // --http-recording-dir; empty: $TMPDIR or /tmp
  bool realtime = false;           // --rt
  int cpu = -1;                    // --cpu; -1: loop not pinned
  int ready_fd = -1;               // --ready-fd; -1: stdout only
};

// A bad or conflicting option value; what() is the one line after "swum-emu: ".
class EmuOptionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The command line ends the program before it starts: --help (exit 0, the help text for stdout)
// or a usage error CLI11 found (its exit code and its text for stderr), as CLI11 words them.
class EmuCliExit : public std::runtime_error {
 public:
  EmuCliExit(int exit_code, std::string out, std::string err)
      : std::runtime_error(err.empty() ? out : err),
        exit_code_(exit_code),
        out_(std::move(out)),
        err_(std::move(err)) {}
  [[nodiscard]] int exit_code() const { return exit_code_; }
  [[nodiscard]] const std::string& out() const { return out_; }
  [[nodiscard]] const std::string& err() const { return err_; }

 private:
  int exit_code_;
  std::string out_;
  std::string err_;
};

// argv (argv[0] names the program in the help) -> options. Throws EmuCliExit, EmuOptionError.
EmuOptions parse_emu_options(int argc, const char* const* argv);

// The options in each part's terms (SI units). Throw EmuOptionError for bad values.
// --min/--max-frequency-hz, --max-amplitude-v, --max-load-n, slews (the limits raised to admit them),
// initial setpoints (checked against the limits), --watchdog-ms.
AmplifierConfig amplifier_config(const EmuOptions& options);
// --modbus; nullopt for "none".
std::optional<ModbusEndpoint> modbus_endpoint(const EmuOptions& options);
ModbusTcpOptions modbus_tcp_options(const EmuOptions& options);
// --node, --telemetry-hz, --heartbeat-ms (used when --can is given).
CanTransportConfig can_transport_config(const EmuOptions& options);
// --can-profile cia402: --node (1..127), --heartbeat-ms when given, and the limits (0x2002/0x2011
// are terminal amplitudes, the amplifier's own unit).
CanopenProfileConfig canopen_profile_config(const EmuOptions& options, const AmplifierLimits& limits);
// --gpio, --encoder-resolution-um, --encoder-max-rate-hz (used when --gpio is given).
GpioConfig gpio_config(const EmuOptions& options);
// --speedup, --rt, --spin-us, --duration-s at --tick-hz; statistics published ~10 times a second.
LoopConfig loop_config(const EmuOptions& options);
// --http and the --http-* options; nullopt when --http is not given. Reads --http-token-file.
std::optional<HttpConfig> http_config(const EmuOptions& options);
// --duration-s at --tick-hz (--clock external).
LockstepConfig lockstep_config(const EmuOptions& options);

}  // namespace swum::emu
