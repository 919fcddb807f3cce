// swum-emu: the virtual two-phase ultrasonic-motor amplifier with its motor attached.
// docs/emulator.md (usage), docs/protocols.md (interfaces).
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>

#include "can_transport.h"
#include "config/parameter_file.h"
#include "emulator_core.h"
#include "gpio_transport.h"
#include "gpiod_lines.h"
#include "modbus_server.h"
#include "model/motor_model.h"
#include "realtime_loop.h"
#include "socketcan_bus.h"

namespace {

std::atomic<bool> g_stop{false};

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path + ": " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Waits for SIGINT/SIGTERM (blocked in every other thread) and sets g_stop.
void signal_waiter(sigset_t set, const std::atomic<bool>* done) {
  while (!done->load()) {
    const timespec timeout{0, 100'000'000};
    const int sig = sigtimedwait(&set, nullptr, &timeout);
    if (sig == SIGINT || sig == SIGTERM) {
      g_stop.store(true);
      return;
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace swum::emu;
  CLI::App app{"swum-emu: two-phase ultrasonic-motor amplifier + motor emulator (docs/emulator.md)"};
  std::string config_path;
  std::string can_interface;
  int node = 1;
  std::string modbus_spec = "tcp://127.0.0.1:1502";
  int modbus_unit = 1;
  std::string gpio_spec;
  double encoder_resolution_um = 10.0;
  double encoder_rate_hz = 20000.0;
  double tick_hz = 10000.0;
  double duration_s = 0.0;
  double speedup = 1.0;
  double spin_us = 0.0;
  double watchdog_ms = 100.0;
  double telemetry_hz = 100.0;
  double heartbeat_ms = 1000.0;
  bool realtime = false;
  int ready_fd = -1;
  int cpu = -1;
  AmplifierConfig amp;
  // Modbus connection limits: taken as text and parsed whole here (one-line errors).
  ModbusTcpOptions modbus_options;
  std::string modbus_idle_text = std::to_string(modbus_options.idle_timeout_ms);
  std::string modbus_frame_text = std::to_string(modbus_options.frame_timeout_ms);
  std::string modbus_evict_text = std::to_string(modbus_options.evict_idle_ms);
  app.add_option("--config", config_path, "motor parameter file (TOML)")->required()->check(CLI::ExistingFile);
  app.add_option("--can", can_interface, "SocketCAN interface (e.g. vcan0); CAN off when absent");
  app.add_option("--node", node, "CAN node id")->check(CLI::Range(1, 127));
  app.add_option("--modbus", modbus_spec, "tcp://HOST:PORT (port 0: any free port), rtu:/dev/TTY:BAUD, or none")
      ->capture_default_str();
  app.add_option("--modbus-unit", modbus_unit, "Modbus RTU unit id")->check(CLI::Range(1, 247));
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
  app.add_option("--gpio", gpio_spec, "CHIP:enable=N,fault=M[,a=K,b=L] (GPIO off when absent)");
  app.add_option("--encoder-resolution-um", encoder_resolution_um, "encoder: mover travel per count")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--encoder-max-rate", encoder_rate_hz, "encoder: max edges per second")
      ->check(CLI::Range(1.0, 1e6))->capture_default_str();
  app.add_option("--tick-hz", tick_hz, "loop rate")->check(CLI::Range(100.0, 100000.0))->capture_default_str();
  app.add_option("--duration", duration_s, "stop after S emulated seconds (0: run until SIGINT/SIGTERM)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--speedup", speedup, "run K times faster than wall time; 0 = as fast as possible")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--watchdog-ms", watchdog_ms, "command timeout while enabled (emulated ms; 0 = off)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--telemetry-hz", telemetry_hz, "CAN telemetry rate (0 = off)")->check(CLI::Range(0.0, 2000.0))
      ->capture_default_str();
  app.add_option("--heartbeat-ms", heartbeat_ms, "CAN heartbeat period (0 = off)")->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--frequency-min", amp.limits.min_frequency_hz, "lowest accepted frequency setpoint (Hz)")
      ->capture_default_str();
  app.add_option("--frequency-max", amp.limits.max_frequency_hz, "highest accepted frequency setpoint (Hz)")
      ->capture_default_str();
  app.add_option("--amplitude-max", amp.limits.max_amplitude_vpp, "highest accepted amplitude setpoint (Vpp)")
      ->capture_default_str();
  app.add_option("--load-max", amp.limits.max_abs_load_n, "largest accepted |load force| (N)")->capture_default_str();
  app.add_option("--frequency-slew", amp.frequency_slew_hz_per_s, "frequency slew limit (Hz/s; 0 = none)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--amplitude-slew", amp.amplitude_slew_vpp_per_s, "amplitude slew limit (Vpp/s; 0 = none)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--frequency", amp.frequency_hz, "initial frequency setpoint (Hz)")->capture_default_str();
  app.add_option("--phase", amp.phase_deg, "initial phase setpoint (deg)")->capture_default_str();
  app.add_flag("--rt", realtime, "try SCHED_FIFO + mlockall (a message, not a failure, when not permitted)");
  app.add_option("--cpu", cpu, "pin the real-time loop to this CPU (transports stay unpinned)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--spin-us", spin_us, "sleep until this long before each tick, then busy-wait (lower wake-up latency, busier CPU)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  app.add_option("--ready-fd", ready_fd, "also write the ready line to this file descriptor");
  CLI11_PARSE(app, argc, argv);
  for (const auto& [option, text, min_ms, value] :
       {std::tuple{"--modbus-idle-timeout-ms", &modbus_idle_text, 0, &modbus_options.idle_timeout_ms},
        std::tuple{"--modbus-frame-timeout-ms", &modbus_frame_text, 1, &modbus_options.frame_timeout_ms},
        std::tuple{"--modbus-evict-idle-ms", &modbus_evict_text, 0, &modbus_options.evict_idle_ms}}) {
    if (const std::string e = parse_milliseconds(*text, min_ms, kMaxTimeoutMs, *value); !e.empty()) {
      std::fprintf(stderr, "swum-emu: %s: %s\n", option, e.c_str());
      return 1;
    }
  }

  // SIGINT/SIGTERM are handled by one thread; block them before any other thread exists.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  if (const int e = pthread_sigmask(SIG_BLOCK, &signals, nullptr); e != 0) {
    std::fprintf(stderr, "swum-emu: pthread_sigmask: %s\n", std::strerror(e));
    return 1;
  }
  std::atomic<bool> signal_thread_done{false};
  std::thread signal_thread(signal_waiter, signals, &signal_thread_done);
  struct Joiner {
    std::atomic<bool>& done;
    std::thread& t;
    ~Joiner() {
      done.store(true);
      if (t.joinable()) t.join();
    }
  } joiner{signal_thread_done, signal_thread};

  try {
    const swum::MotorParameters parameters = swum::parse_motor_parameters(read_file(config_path), config_path);
    const swum::MotorModel model(parameters);
    if (amp.limits.min_frequency_hz > amp.limits.max_frequency_hz)
      throw std::runtime_error("--frequency-min is above --frequency-max");
    amp.watchdog_s = watchdog_ms * 1e-3;
    amp.limits.max_frequency_slew_hz_per_s = std::max(amp.limits.max_frequency_slew_hz_per_s, amp.frequency_slew_hz_per_s);
    amp.limits.max_amplitude_slew_vpp_per_s =
        std::max(amp.limits.max_amplitude_slew_vpp_per_s, amp.amplitude_slew_vpp_per_s);
    if (validate([&] {
          Command c;
          c.fields = Command::kFrequency | Command::kPhase;
          c.frequency_hz = amp.frequency_hz;
          c.phase_deg = amp.phase_deg;
          return c;
        }(), amp.limits) != Reason::none)
      throw std::runtime_error("initial --frequency / --phase outside the accepted limits");

    auto shared = std::make_unique<SharedState>();
    CoreConfig core_config;
    core_config.tick_hz = tick_hz;
    core_config.amplifier = amp;
    EmulatorCore core(model, core_config, *shared);
    core.tick();  // publish a first snapshot before any transport answers

    std::string ready = "swum-emu ready";
    std::unique_ptr<ModbusTcpServer> modbus_tcp;
    std::unique_ptr<ModbusRtuServer> modbus_rtu;
    if (modbus_spec != "none") {
      ModbusEndpoint endpoint;
      if (const std::string e = parse_modbus_endpoint(modbus_spec, endpoint); !e.empty())
        throw std::runtime_error("--modbus: " + e);
      if (endpoint.tcp) {
        if (endpoint.host == "0.0.0.0")
          std::fprintf(stderr, "swum-emu: warning: Modbus TCP bound to all interfaces (0.0.0.0) as asked\n");
        modbus_tcp = std::make_unique<ModbusTcpServer>(endpoint.host, endpoint.port, *shared, amp.limits, modbus_options);
        ready += " modbus=tcp://" + endpoint.host + ":" + std::to_string(modbus_tcp->port());
      } else {
        modbus_rtu = std::make_unique<ModbusRtuServer>(endpoint.device, endpoint.baud, modbus_unit, *shared, amp.limits,
                                                       modbus_options.frame_timeout_ms);
        ready += " modbus=rtu:" + endpoint.device + ":" + std::to_string(endpoint.baud);
      }
    }
    std::unique_ptr<CanTransport> can;
    const swum::io::SocketCanBus* can_rx = nullptr;  // owned by `can`; kernel drop counter
    if (!can_interface.empty()) {
      CanTransportConfig cc;
      cc.node = static_cast<std::uint8_t>(node);
      cc.telemetry_hz = telemetry_hz;
      cc.heartbeat_s = heartbeat_ms * 1e-3;
      // Separate sockets for receiving (filtered) and sending (no filters needed).
      auto rx = std::make_unique<swum::io::SocketCanBus>(can_interface);
      can_rx = rx.get();
      swum::io::SocketCanBus::Options tx_options;
      tx_options.receive_error_frames = false;
      auto tx = std::make_unique<swum::io::SocketCanBus>(can_interface, tx_options);
      const std::array<swum::io::CanFilter, 1> none{swum::io::CanFilter{0x7FF, 0x7FF, true}};  // nothing
      if (const auto r = tx->set_filters(none); !r.ok()) throw std::runtime_error("CAN: " + r.message);
      can = std::make_unique<CanTransport>(std::move(rx), std::move(tx), cc, *shared, amp.limits);
      ready += " can=" + can_interface + " node=" + std::to_string(node);
    }
    std::unique_ptr<swum::io::GpiodLines> gpio_lines;
    std::unique_ptr<GpioTransport> gpio;
    if (!gpio_spec.empty()) {
      GpioConfig gc;
      if (const std::string e = parse_gpio_spec(gpio_spec, gc); !e.empty()) throw std::runtime_error("--gpio: " + e);
      gc.encoder_resolution_m = encoder_resolution_um * 1e-6;
      gc.max_edge_rate_hz = encoder_rate_hz;
      gpio_lines = std::make_unique<swum::io::GpiodLines>();
      gpio = std::make_unique<GpioTransport>(*gpio_lines, gc, *shared);
      ready += " gpio=" + gc.chip;
    }

    LoopConfig loop_config;
    loop_config.speedup = speedup;
    loop_config.realtime = realtime;
    loop_config.spin_s = spin_us * 1e-6;
    loop_config.stats_every_ticks = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(tick_hz / 10.0));
    if (duration_s > 0.0) loop_config.max_ticks = static_cast<std::uint64_t>(std::llround(duration_s * tick_hz));
    if (realtime) std::fprintf(stderr, "swum-emu: %s\n", try_realtime(loop_config.priority).c_str());

    if (modbus_tcp) modbus_tcp->start();
    if (modbus_rtu) modbus_rtu->start();
    if (can) can->start();
    if (gpio) gpio->start();

    char tail[160];
    std::snprintf(tail, sizeof tail, " tick_hz=%g speedup=%g watchdog_ms=%g pid=%d", tick_hz, speedup, watchdog_ms,
                  static_cast<int>(getpid()));
    ready += tail;
    std::printf("%s\n", ready.c_str());
    std::fflush(stdout);
    if (ready_fd >= 0) {
      const std::string line = ready + "\n";
      if (::write(ready_fd, line.data(), line.size()) < 0)
        std::fprintf(stderr, "swum-emu: --ready-fd %d: %s\n", ready_fd, std::strerror(errno));
      ::close(ready_fd);
    }

    if (cpu >= 0) {  // after the transports started: only this (the loop's) thread is pinned
      cpu_set_t set;
      CPU_ZERO(&set);
      CPU_SET(cpu, &set);
      if (const int e = pthread_setaffinity_np(pthread_self(), sizeof set, &set); e != 0)
        std::fprintf(stderr, "swum-emu: --cpu %d: pthread_setaffinity_np: %s (loop not pinned)\n", cpu, std::strerror(e));
    }
    RealtimeLoop loop(core, loop_config);
    loop.run(g_stop);
    core.shut_down();  // drive off, published before the transports stop

    if (gpio) gpio->stop();
    if (can) can->stop();
    if (modbus_tcp) modbus_tcp->stop();
    if (modbus_rtu) modbus_rtu->stop();

    const LoopStatsSummary summary = loop.statistics().summary();
    const Telemetry& t = core.telemetry();
    std::printf("swum-emu stopped: %s after %.3f s emulated in %.3f s wall; state %s, fault %s\n",
                g_stop.load() ? "signal" : "duration", t.sim_time_s, loop.wall_seconds(), to_string(t.state),
                to_string(t.fault));
    std::printf("%s", format_summary(summary, tick_hz).c_str());
    std::printf("  resyncs   %llu; commands applied %llu, rejected %llu (queue full %llu)\n",
                static_cast<unsigned long long>(loop.resyncs()), static_cast<unsigned long long>(t.applied_commands),
                static_cast<unsigned long long>(shared->rejects.count.load()),
                static_cast<unsigned long long>(shared->queue_full.load()));
    if (modbus_tcp)
      std::printf("  modbus    %llu requests, %llu exceptions, %llu connections\n",
                  static_cast<unsigned long long>(modbus_tcp->stats().requests.load()),
                  static_cast<unsigned long long>(modbus_tcp->stats().exceptions.load()),
                  static_cast<unsigned long long>(modbus_tcp->stats().connections.load()));
    if (modbus_tcp)
      std::printf("%s", format_drops("modbus tcp closed:", modbus_tcp->stats().drops,
                                     {Drop::no_slot, Drop::evicted, Drop::idle, Drop::frame_timeout,
                                      Drop::reply_timeout})
                            .c_str());
    if (modbus_rtu) {
      std::printf("  modbus    %llu requests, %llu exceptions, %llu line errors\n",
                  static_cast<unsigned long long>(modbus_rtu->stats().requests.load()),
                  static_cast<unsigned long long>(modbus_rtu->stats().exceptions.load()),
                  static_cast<unsigned long long>(modbus_rtu->stats().receive_errors.load()));
      std::printf("%s", format_drops("modbus rtu discarded:", modbus_rtu->stats().drops,
                                     {Drop::other_unit, Drop::bad_crc, Drop::bad_length, Drop::partial_frame,
                                      Drop::frame_timeout})
                            .c_str());
    }
    if (can)
      std::printf("  can       rx %llu (accepted %llu, rejected %llu, receive errors %llu), tx %llu (dropped %llu, "
                  "send errors %llu), error frames %llu, bus-off %llu\n",
                  static_cast<unsigned long long>(can->stats().rx_frames.load()),
                  static_cast<unsigned long long>(can->stats().accepted.load()),
                  static_cast<unsigned long long>(can->stats().rejected.load()),
                  static_cast<unsigned long long>(can->stats().rx_errors.load()),
                  static_cast<unsigned long long>(can->stats().tx_frames.load()),
                  static_cast<unsigned long long>(can->stats().tx_dropped.load()),
                  static_cast<unsigned long long>(can->stats().tx_errors.load()),
                  static_cast<unsigned long long>(can->stats().error_frames.load()),
                  static_cast<unsigned long long>(can->stats().bus_off.load()));
    if (can) {
      const Histogram& age = can->receive_age();
      std::printf("  can rx    kernel timestamps %llu, missing %llu, implausible %llu; kernel drops %llu; "
                  "kernel rx -> read p50 %.1f us  p99 %.1f us  max %.1f us\n",
                  static_cast<unsigned long long>(can->stats().rx_stamped.load()),
                  static_cast<unsigned long long>(can->stats().rx_stamp_missing.load()),
                  static_cast<unsigned long long>(can->stats().rx_stamp_implausible.load()),
                  static_cast<unsigned long long>(can_rx ? can_rx->kernel_drops() : 0),
                  static_cast<double>(age.percentile(0.50)) / 1e3, static_cast<double>(age.percentile(0.99)) / 1e3,
                  static_cast<double>(age.max()) / 1e3);
    }
    std::fflush(stdout);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "swum-emu: %s\n", e.what());
    return 1;
  }
}
