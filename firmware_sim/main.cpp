// swum-emu: the virtual two-phase ultrasonic-motor amplifier with its motor attached.
// docs/emulator.md (usage), docs/protocols.md (interfaces).
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include "config/parameter_file.h"
#include "emu_options.h"
#include "emulator_core.h"
#include "gpiod_lines.h"
#include "model/motor_model.h"
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
  EmuOptions o;
  try {
    o = parse_emu_options(argc, argv);
  } catch (const EmuCliExit& e) {
    std::fputs(e.out().c_str(), stdout);
    std::fputs(e.err().c_str(), stderr);
    return e.exit_code();
  } catch (const EmuOptionError& e) {
    std::fprintf(stderr, "swum-emu: %s\n", e.what());
    return 1;
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
    const swum::MotorParameters parameters = swum::parse_motor_parameters(read_file(o.config_path), o.config_path);
    const swum::MotorModel model(parameters);
    const AmplifierConfig amp = amplifier_config(o);

    auto shared = std::make_unique<SharedState>();
    CoreConfig core_config;
    core_config.tick_hz = o.tick_hz;
    core_config.amplifier = amp;
    EmulatorCore core(model, core_config, *shared);
    core.tick();  // publish a first snapshot before any transport answers

    std::string ready = "swum-emu ready";
    std::unique_ptr<ModbusTcpServer> modbus_tcp;
    std::unique_ptr<ModbusRtuServer> modbus_rtu;
    if (const std::optional<ModbusEndpoint> modbus = modbus_endpoint(o)) {
      const ModbusEndpoint& endpoint = *modbus;
      if (endpoint.tcp) {
        if (endpoint.host == "0.0.0.0")
          std::fprintf(stderr, "swum-emu: warning: Modbus TCP bound to all interfaces (0.0.0.0) as asked\n");
        modbus_tcp = std::make_unique<ModbusTcpServer>(endpoint.host, endpoint.port, *shared, amp.limits, modbus_tcp_options(o));
        ready += " modbus=tcp://" + endpoint.host + ":" + std::to_string(modbus_tcp->port());
      } else {
        modbus_rtu = std::make_unique<ModbusRtuServer>(endpoint.device, endpoint.baud, o.modbus_unit, *shared, amp.limits,
                                                       o.modbus_frame_timeout_ms);
        ready += " modbus=rtu:" + endpoint.device + ":" + std::to_string(endpoint.baud);
      }
    }
    std::unique_ptr<CanTransport> can;
    const swum::io::SocketCanBus* can_rx = nullptr;  // owned by `can`; kernel drop counter
    if (!o.can_interface.empty()) {
      // Separate sockets for receiving (filtered) and sending (no filters needed).
      auto rx = std::make_unique<swum::io::SocketCanBus>(o.can_interface);
      can_rx = rx.get();
      swum::io::SocketCanBus::Options tx_options;
      tx_options.receive_error_frames = false;
      auto tx = std::make_unique<swum::io::SocketCanBus>(o.can_interface, tx_options);
      const std::array<swum::io::CanFilter, 1> none{swum::io::CanFilter{0x7FF, 0x7FF, true}};  // nothing
      if (const auto r = tx->set_filters(none); !r.ok()) throw std::runtime_error("CAN: " + r.message);
      can = std::make_unique<CanTransport>(std::move(rx), std::move(tx), can_transport_config(o), *shared, amp.limits);
      ready += " can=" + o.can_interface + " node=" + std::to_string(o.can_node);
    }
    std::unique_ptr<swum::io::GpiodLines> gpio_lines;
    std::unique_ptr<GpioTransport> gpio;
    if (!o.gpio_spec.empty()) {
      const GpioConfig gc = gpio_config(o);
      gpio_lines = std::make_unique<swum::io::GpiodLines>();
      gpio = std::make_unique<GpioTransport>(*gpio_lines, gc, *shared);
      ready += " gpio=" + gc.chip;
    }

    const LoopConfig loop_options = loop_config(o);
    if (o.realtime) std::fprintf(stderr, "swum-emu: %s\n", try_realtime(loop_options.priority).c_str());

    if (modbus_tcp) modbus_tcp->start();
    if (modbus_rtu) modbus_rtu->start();
    if (can) can->start();
    if (gpio) gpio->start();

    char tail[160];
    std::snprintf(tail, sizeof tail, " tick_hz=%g speedup=%g watchdog_ms=%g pid=%d", o.tick_hz, o.speedup, o.watchdog_ms,
                  static_cast<int>(getpid()));
    ready += tail;
    std::printf("%s\n", ready.c_str());
    std::fflush(stdout);
    if (o.ready_fd >= 0) {
      const std::string line = ready + "\n";
      if (::write(o.ready_fd, line.data(), line.size()) < 0)
        std::fprintf(stderr, "swum-emu: --ready-fd %d: %s\n", o.ready_fd, std::strerror(errno));
      ::close(o.ready_fd);
    }

    if (o.cpu >= 0) {  // after the transports started: only this (the loop's) thread is pinned
      cpu_set_t set;
      CPU_ZERO(&set);
      CPU_SET(o.cpu, &set);
      if (const int e = pthread_setaffinity_np(pthread_self(), sizeof set, &set); e != 0)
        std::fprintf(stderr, "swum-emu: --cpu %d: pthread_setaffinity_np: %s (loop not pinned)\n", o.cpu, std::strerror(e));
    }
    RealtimeLoop loop(core, loop_options);
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
    std::printf("%s", format_summary(summary, o.tick_hz).c_str());
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
