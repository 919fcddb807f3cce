#include "app/emu_app.h"

#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "core/emulator_core.h"
#include "core/scenario.h"
#include "core/trace.h"
#include "formats/number_format.h"
#include "formats/parameter_file.h"
#include "gpiod_lines.h"
#include "model/motor_model.h"
#include "socketcan_bus.h"

namespace swum::emu {
namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path + ": " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// SIGINT/SIGTERM: blocked in the constructing thread (so in every thread started after it) and
// waited for by a thread of their own, which sets stop().
class SignalStop {
 public:
  SignalStop() {
    sigemptyset(&signals_);
    sigaddset(&signals_, SIGINT);
    sigaddset(&signals_, SIGTERM);
    if (const int e = pthread_sigmask(SIG_BLOCK, &signals_, nullptr); e != 0)
      throw std::runtime_error(std::string("pthread_sigmask: ") + std::strerror(e));
    waiter_ = std::thread([this] { wait(); });
  }
  ~SignalStop() {
    done_.store(true);
    waiter_.join();
  }
  SignalStop(const SignalStop&) = delete;
  SignalStop& operator=(const SignalStop&) = delete;
  [[nodiscard]] const std::atomic<bool>& stop() const { return stop_; }

 private:
  void wait() {
    while (!done_.load()) {
      const timespec timeout{0, 100'000'000};
      const int sig = sigtimedwait(&signals_, nullptr, &timeout);
      if (sig == SIGINT || sig == SIGTERM) {
        stop_.store(true);
        return;
      }
    }
  }
  sigset_t signals_{};
  std::atomic<bool> stop_{false};
  std::atomic<bool> done_{false};
  std::thread waiter_;
};

// The transports the options ask for, opened (bound, requested) but not started. Members are
// destroyed in reverse order: GPIO, CAN, Modbus.
struct Transports {
  std::unique_ptr<ModbusTcpServer> modbus_tcp;
  std::unique_ptr<ModbusRtuServer> modbus_rtu;
  std::unique_ptr<CanTransport> can;
  const CanopenProfile* canopen = nullptr;   // owned by `can` with --can-profile cia402
  const io::SocketCanBus* can_rx = nullptr;  // owned by `can`; kernel drop counter
  std::unique_ptr<io::GpiodLines> gpio_lines;
  std::unique_ptr<GpioTransport> gpio;
  std::FILE* can_log = nullptr;  // --record-can; closed by close_can_log() after stop()
  std::string ready;             // what the ready line says about them: " modbus=... can=... gpio=..."

  void start() {
    if (modbus_tcp) modbus_tcp->start();
    if (modbus_rtu) modbus_rtu->start();
    if (can) can->start();
    if (gpio) gpio->start();
  }
  void stop() {
    if (gpio) gpio->stop();
    if (can) can->stop();
    if (modbus_tcp) modbus_tcp->stop();
    if (modbus_rtu) modbus_rtu->stop();
  }
  // Empty when the CAN log (if any) was written whole, else why not.
  std::string close_can_log(const std::string& path) {
    if (can_log == nullptr) return {};
    const bool ok = std::ferror(can_log) == 0 && std::fflush(can_log) == 0;
    const int e = errno;
    const bool closed = std::fclose(can_log) == 0;
    can_log = nullptr;
    return ok && closed ? std::string() : "--record-can " + path + ": write failed: " + std::strerror(e);
  }
  ~Transports() {
    stop();  // no transport thread may still write to the CAN log
    if (can_log != nullptr) std::fclose(can_log);
  }
};

void open_modbus(const EmuOptions& o, SharedState& shared, const AmplifierLimits& limits, Transports& t) {
  const std::optional<ModbusEndpoint> endpoint = modbus_endpoint(o);
  if (!endpoint) return;
  if (endpoint->tcp) {
    if (endpoint->host == "0.0.0.0")
      std::fprintf(stderr, "swum-emu: warning: Modbus TCP bound to all interfaces (0.0.0.0) as asked\n");
    t.modbus_tcp = std::make_unique<ModbusTcpServer>(endpoint->host, endpoint->port, shared, limits,
                                                     modbus_tcp_options(o));
    t.ready += " modbus=tcp://" + endpoint->host + ":" + std::to_string(t.modbus_tcp->port());
  } else {
    t.modbus_rtu = std::make_unique<ModbusRtuServer>(endpoint->device, endpoint->baud, o.modbus_unit, shared, limits,
                                                     o.modbus_frame_timeout_ms);
    t.ready += " modbus=rtu:" + endpoint->device + ":" + std::to_string(endpoint->baud);
  }
}

void open_can(const EmuOptions& o, SharedState& shared, const AmplifierLimits& limits, Transports& t) {
  if (o.can_interface.empty()) return;
  // Separate sockets for receiving (filtered) and sending (no filters needed).
  auto rx = std::make_unique<io::SocketCanBus>(o.can_interface);
  t.can_rx = rx.get();
  io::SocketCanBus::Options tx_options;
  tx_options.receive_error_frames = false;
  auto tx = std::make_unique<io::SocketCanBus>(o.can_interface, tx_options);
  const std::array<io::CanFilter, 1> none{
      io::CanFilter{io::kCanStandardIdMax, io::kCanStandardIdMax, true}};  // nothing
  if (const auto r = tx->set_filters(none); !r.ok()) throw std::runtime_error("CAN: " + r.message);
  CanTransportConfig config = can_transport_config(o);
  if (!o.record_can_path.empty()) {
    t.can_log = std::fopen(o.record_can_path.c_str(), "w");
    if (t.can_log == nullptr)
      throw std::runtime_error("--record-can " + o.record_can_path + ": " + std::strerror(errno));
    config.can_log = t.can_log;
  }
  if (o.can_profile == "cia402") {
    auto profile = std::make_unique<CanopenProfile>(canopen_profile_config(o, limits), shared);
    t.canopen = profile.get();
    t.can = std::make_unique<CanTransport>(std::move(rx), std::move(tx), std::move(profile), config, shared, limits);
  } else {
    t.can = std::make_unique<CanTransport>(std::move(rx), std::move(tx), config, shared, limits);
  }
  t.ready += " can=" + o.can_interface + " node=" + std::to_string(o.can_node) + " can_profile=" + o.can_profile;
}

void open_gpio(const EmuOptions& o, SharedState& shared, Transports& t) {
  if (o.gpio_spec.empty()) return;
  const GpioConfig config = gpio_config(o);
  t.gpio_lines = std::make_unique<io::GpiodLines>();
  t.gpio = std::make_unique<GpioTransport>(*t.gpio_lines, config, shared);
  t.ready += " gpio=" + config.chip;
}

// The ready line to stdout and, with --ready-fd, to that descriptor (then closed).
void announce_ready(const EmuOptions& o, const std::string& transports) {
  char tail[160];
  if (o.external_clock) {
    std::snprintf(tail, sizeof tail, " tick_hz=%g clock=external watchdog_ms=%g pid=%d", o.tick_hz, o.watchdog_ms,
                  static_cast<int>(getpid()));
  } else {
    std::snprintf(tail, sizeof tail, " tick_hz=%g speedup=%g watchdog_ms=%g pid=%d", o.tick_hz, o.speedup,
                  o.watchdog_ms, static_cast<int>(getpid()));
  }
  std::string ready = "swum-emu ready" + transports + tail;
  if (o.config_is_default) ready += " default_config=" + o.config_path;
  std::printf("%s\n", ready.c_str());
  std::fflush(stdout);
  if (o.ready_fd >= 0) {
    const std::string line = ready + "\n";
    if (::write(o.ready_fd, line.data(), line.size()) < 0)
      std::fprintf(stderr, "swum-emu: --ready-fd %d: %s\n", o.ready_fd, std::strerror(errno));
    ::close(o.ready_fd);
  }
}

// Pins the calling thread (the loop's) to `cpu`; a message, not a failure, when refused.
void pin_loop_thread(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  if (const int e = pthread_setaffinity_np(pthread_self(), sizeof set, &set); e != 0)
    std::fprintf(stderr, "swum-emu: --cpu %d: pthread_setaffinity_np: %s (loop not pinned)\n", cpu, std::strerror(e));
}

[[gnu::format(printf, 2, 3)]] void append(std::string& out, const char* format, ...) {
  std::va_list args;
  va_start(args, format);
  std::va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  if (n > 0) {
    const std::size_t at = out.size();
    out.resize(at + static_cast<std::size_t>(n) + 1);
    std::vsnprintf(out.data() + at, static_cast<std::size_t>(n) + 1, format, again);
    out.resize(at + static_cast<std::size_t>(n));
  }
  va_end(again);
}

unsigned long long u(std::uint64_t value) { return static_cast<unsigned long long>(value); }

// --scenario and every --inject, as one timeline (stable by time: the file's order, then the
// injections'). Throws ScenarioError naming file:line or the --inject text.
Scenario load_scenario(const EmuOptions& o) {
  Scenario scenario;
  if (!o.scenario_path.empty()) scenario = parse_scenario(read_file(o.scenario_path), o.scenario_path);
  for (const std::string& text : o.injections) scenario.events.push_back(parse_injection(text));
  std::stable_sort(scenario.events.begin(), scenario.events.end(),
                   [](const ScenarioEvent& a, const ScenarioEvent& b) { return a.at_s < b.at_s; });
  return scenario;
}

// The timeline as canonical text (what a replay must play again).
std::string scenario_text(const Scenario& scenario) {
  std::string text = "seed=" + std::to_string(scenario.seed) + "\n";
  for (const ScenarioEvent& e : scenario.events) text += format_event(e) + "\n";
  return text;
}

// What changes a run's telemetry besides the commands: a replay must run with the same.
TraceSettings trace_settings(const EmuOptions& o, const std::string& config_text, const Scenario& scenario) {
  TraceSettings s;
  s.add("config_fnv1a", fnv1a_hex(config_text));
  s.add("scenario_fnv1a", fnv1a_hex(scenario_text(scenario)));
  for (const auto& [name, value] : {std::pair{"tick_hz", o.tick_hz},
                                    {"watchdog_ms", o.watchdog_ms},
                                    {"frequency_min", o.frequency_min_hz},
                                    {"frequency_max", o.frequency_max_hz},
                                    {"amplitude_max", o.max_amplitude_v},
                                    {"load_max", o.load_max_n},
                                    {"frequency_slew", o.frequency_slew_hz_per_s},
                                    {"amplitude_slew", o.amplitude_slew_v_per_s},
                                    {"frequency", o.frequency_hz},
                                    {"phase", o.phase_deg}})
    s.add(name, shortest_decimal(value));
  return s;
}

// --replay: the trace's inputs into a fresh core, no transports, no clock. 0 identical, 3 not.
int run_replay(const EmuOptions& o, const MotorModel& model, const CoreConfig& core_config,
               const std::string& config_text, const Scenario& scenario, const std::atomic<bool>& stop) {
  std::ifstream in(o.replay_path, std::ios::binary);
  if (!in) throw std::runtime_error("--replay " + o.replay_path + ": " + std::strerror(errno));
  const Trace trace = read_trace(in, o.replay_path);
  if (const std::string e = compare_settings(trace.settings, trace_settings(o, config_text, scenario)); !e.empty())
    throw EmuOptionError("--replay " + o.replay_path + ": " + e);
  auto shared = std::make_unique<SharedState>();
  EmulatorCore core(model, core_config, *shared);
  if (!scenario.events.empty()) core.set_scenario(scenario, nullptr);
  const ReplayResult r = replay(trace, core, *shared, &stop);
  if (r.stopped) {
    std::printf("swum-emu replay: stopped by a signal after %llu identical ticks\n", u(r.ticks));
    return 130;
  }
  if (!r.identical) {
    std::printf("swum-emu replay: DIFFERENT at %s (%llu ticks identical before it, %llu commands fed)\n",
                r.difference.c_str(), u(r.ticks - 1), u(r.commands));
    return 3;
  }
  std::printf("swum-emu replay: identical: %llu ticks, %llu commands (%s)\n", u(r.ticks), u(r.commands),
              o.replay_path.c_str());
  return 0;
}

}  // namespace

int run_emulator(const EmuOptions& o) {
  const SignalStop signals;  // before any other thread exists
  const std::string config_text = read_file(o.config_path);
  const MotorParameters parameters = parse_motor_parameters(config_text, o.config_path);
  const MotorModel model(parameters);
  const AmplifierConfig amp = amplifier_config(o);

  auto shared = std::make_unique<SharedState>();
  CoreConfig core_config;
  core_config.tick_hz = o.tick_hz;
  core_config.amplifier = amp;
  core_config.external_clock = o.external_clock || !o.replay_path.empty();
  const Scenario scenario = load_scenario(o);
  if (!o.replay_path.empty()) return run_replay(o, model, core_config, config_text, scenario, signals.stop());
  LockstepClock lockstep;
  if (o.external_clock) shared->lockstep = &lockstep;
  shared->speedup = o.speedup;
  shared->tick_hz = o.tick_hz;
  EmulatorCore core(model, core_config, *shared);
  const std::optional<HttpConfig> http = http_config(o);
  // The API's run-time faults join a scenario's timeline: with --http there is one, even empty.
  if (!scenario.events.empty() || http) core.set_scenario(scenario);
  std::unique_ptr<TraceRecorder> recorder;
  if (!o.record_path.empty()) {
    recorder = std::make_unique<TraceRecorder>(o.record_path, trace_settings(o, config_text, scenario));
    core.set_observer(recorder.get());
  }
  Transports transports;
  open_modbus(o, *shared, amp.limits, transports);
  open_can(o, *shared, amp.limits, transports);
  open_gpio(o, *shared, transports);
  // A first snapshot before any transport answers (none has started): after they are built, so
  // that a CiA 402 drive (its profile publishes the request when built) has taken its first
  // transition (not ready to switch on -> switch on disabled) before a master sees a statusword.
  core.tick();
  std::unique_ptr<HttpApi> api;
  if (http) {
    api = std::make_unique<HttpApi>(*http, *shared, model);
    if (!is_loopback_host(http->host))
      std::fprintf(stderr,
                   "swum-emu: warning: the HTTP API is bound to %s as asked: anyone who can reach it can "
                   "inject faults%s\n",
                   http->host.c_str(), http->token.empty() ? " (no --http-token)" : "");
    transports.ready += " http=http://" + http->host + ":" + std::to_string(api->port());
  }

  const LoopConfig loop_options = loop_config(o);
  if (o.realtime) std::fprintf(stderr, "swum-emu: %s\n", try_realtime(loop_options.priority).c_str());
  transports.start();
  if (api) api->start();
  announce_ready(o, transports.ready);
  if (o.cpu >= 0) pin_loop_thread(o.cpu);  // after the transports started: only the loop's thread

  RealtimeLoop loop(core, loop_options);
  LockstepLoop lockstep_loop(core, lockstep, lockstep_config(o));
  std::optional<std::uint64_t> lockstep_ticks;
  if (o.external_clock) {
    lockstep_ticks = lockstep_loop.run(signals.stop());  // closes the clock: every waiting step is answered
  } else {
    loop.run(signals.stop());
  }
  core.shut_down();  // drive off, published before the transports stop
  transports.stop();
  // A client still trickling a request must not keep the emulator from exiting: after 3 s the
  // API is left to the process's end (its threads still use it: it is never destroyed).
  bool api_abandoned = false;
  HttpApi* const api_view = api.get();  // the exit report's counts, even when abandoned
  if (api && !api->stop()) {
    api_abandoned = true;
    static_cast<void>(api.release());  // never destroyed: its threads still run on it
    std::fprintf(stderr, "swum-emu: --http: a connection was still open 3 s after the stop; exiting without it\n");
  }
  std::string record_error = transports.close_can_log(o.record_can_path);
  if (recorder) {
    core.set_observer(nullptr);
    if (const std::string e = recorder->close(); !e.empty()) record_error = e;
  }

  const Telemetry& t = core.telemetry();
  ExitStatistics s;
  s.stopped_by_signal = signals.stop().load();
  s.emulated_s = t.sim_time_s;
  s.wall_s = o.external_clock ? lockstep_loop.wall_seconds() : loop.wall_seconds();
  s.state = t.state;
  s.fault = t.fault;
  s.tick_hz = o.tick_hz;
  s.loop = loop.statistics().summary();
  s.lockstep_ticks = lockstep_ticks;
  s.resyncs = loop.resyncs();
  s.commands_applied = t.applied_commands;
  s.commands_rejected = shared->rejects.count.load();
  s.queue_full = shared->queue_full.load();
  if (api_view != nullptr) s.http = &api_view->stats();
  if (transports.modbus_tcp) s.modbus_tcp = &transports.modbus_tcp->stats();
  if (transports.modbus_rtu) s.modbus_rtu = &transports.modbus_rtu->stats();
  if (transports.can) {
    s.can = &transports.can->stats();
    s.can_receive_age = &transports.can->receive_age();
    s.can_kernel_drops = transports.can_rx ? transports.can_rx->kernel_drops() : 0;
  }
  std::fputs(format_exit_report(s).c_str(), stdout);
  std::fflush(stdout);
  int status = 0;
  if (!record_error.empty()) {  // the run itself is reported above; the trace is incomplete
    std::fprintf(stderr, "swum-emu: %s\n", record_error.c_str());
    status = 1;
  }
  if (api_abandoned) {  // its threads use this function's objects: end here, before they go
    std::fflush(nullptr);
    std::_Exit(status);
  }
  return status;
}

std::string format_exit_report(const ExitStatistics& s) {
  std::string out;
  append(out, "swum-emu stopped: %s after %.3f s emulated in %.3f s wall; state %s, fault %s\n",
         s.stopped_by_signal ? "signal" : "duration", s.emulated_s, s.wall_s, to_string(s.state), to_string(s.fault));
  if (s.lockstep_ticks) {
    append(out, "lockstep: %llu ticks stepped by the controller at %g Hz (clock external: no loop timing)\n",
           u(*s.lockstep_ticks), s.tick_hz);
  } else {
    out += format_summary(s.loop, s.tick_hz);
  }
  append(out, "  resyncs   %llu; commands applied %llu, rejected %llu (queue full %llu)\n", u(s.resyncs),
         u(s.commands_applied), u(s.commands_rejected), u(s.queue_full));
  if (const ModbusStats* m = s.modbus_tcp) {
    append(out, "  modbus    %llu requests, %llu exceptions, %llu connections\n", u(m->requests.load()),
           u(m->exceptions.load()), u(m->connections.load()));
    if (m->withheld_replies.load() + m->delayed_replies.load() > 0)
      append(out, "  modbus    scenario: replies withheld %llu, delayed %llu\n", u(m->withheld_replies.load()),
             u(m->delayed_replies.load()));
    out += format_drops("modbus tcp closed:", m->drops,
                        {Drop::no_slot, Drop::evicted, Drop::idle, Drop::frame_timeout, Drop::reply_timeout,
                         Drop::bad_header, Drop::too_long});
  }
  if (const ModbusStats* m = s.modbus_rtu) {
    append(out, "  modbus    %llu requests, %llu exceptions, %llu line errors\n", u(m->requests.load()),
           u(m->exceptions.load()), u(m->receive_errors.load()));
    out += format_drops("modbus rtu discarded:", m->drops,
                        {Drop::other_unit, Drop::bad_crc, Drop::bad_length, Drop::partial_frame, Drop::frame_timeout});
  }
  if (const HttpStats* h = s.http) {
    append(out,
           "  http      %llu requests, %llu refused; stream events %llu, streams refused %llu; faults queued %llu\n",
           u(h->requests.load()), u(h->refused.load()), u(h->stream_events.load()), u(h->stream_refused.load()),
           u(h->faults_queued.load()));
  }
  if (const CanStats* c = s.can) {
    append(out,
           "  can       rx %llu (accepted %llu, rejected %llu, receive errors %llu), tx %llu (dropped %llu, "
           "send errors %llu), error frames %llu, bus-off %llu\n",
           u(c->rx_frames.load()), u(c->accepted.load()), u(c->rejected.load()), u(c->rx_errors.load()),
           u(c->tx_frames.load()), u(c->tx_dropped.load()), u(c->tx_errors.load()), u(c->error_frames.load()),
           u(c->bus_off.load()));
    if (c->syncs.load() + c->bus_off_discarded.load() > 0)
      append(out, "  can       lockstep SYNCs %llu; scenario bus-off: frames discarded %llu\n", u(c->syncs.load()),
             u(c->bus_off_discarded.load()));
    const Histogram empty;
    const Histogram& age = s.can_receive_age ? *s.can_receive_age : empty;
    append(out,
           "  can rx    kernel timestamps %llu, missing %llu, implausible %llu; kernel drops %llu; "
           "kernel rx -> read p50 %.1f us  p99 %.1f us  max %.1f us\n",
           u(c->rx_stamped.load()), u(c->rx_stamp_missing.load()), u(c->rx_stamp_implausible.load()),
           u(s.can_kernel_drops), static_cast<double>(age.percentile(0.50)) / 1e3,
           static_cast<double>(age.percentile(0.99)) / 1e3, static_cast<double>(age.max()) / 1e3);
  }
  return out;
}

}  // namespace swum::emu
