// Modbus transports on libmodbus: a TCP server (modbus_tcp_server.cpp: one thread accepting and
// enforcing the connection deadlines, one thread per client, up to max_clients at once) and an
// RTU server on a serial device (modbus_rtu_server.cpp: one thread, its own framing with
// deadlines by protocol/modbus_rtu; libmodbus builds the replies). Both serve a request the same
// way (modbus_serve): checked by protocol/modbus_codec (pure), accepted writes to the command
// queue, reads from the latest telemetry snapshot. The loop never waits for these threads.
// Who gets a slot and what is cut off: docs/emulator.md, "Modbus: no client locks the others out".
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/amplifier.h"
#include "core/loop_statistics.h"
#include "core/shared_state.h"
#include "endpoint.h"

namespace swum::emu {

// The server listens where a protocol::ModbusEndpoint says (--modbus).
using protocol::ModbusEndpoint;
using protocol::parse_modbus_endpoint;

struct ModbusStats {
  std::atomic<std::uint64_t> requests{0};
  std::atomic<std::uint64_t> exceptions{0};
  std::atomic<std::uint64_t> connections{0};     // TCP: taken into a slot
  std::atomic<std::uint64_t> receive_errors{0};  // TCP: libmodbus framing errors; RTU: read errors
  DropCounters drops;                            // connections closed / frames discarded by the server
  // Scenario communication faults (docs/scenarios.md): replies withheld (modbus_drop, FC04 in a
  // telemetry_silence) and replies sent late (modbus_delay).
  std::atomic<std::uint64_t> withheld_replies{0};
  std::atomic<std::uint64_t> delayed_replies{0};
};

// Limits of the Modbus TCP server (swum-emu options --modbus-*-ms; defaults documented in
// docs/emulator.md).
struct ModbusTcpOptions {
  int max_clients = 16;
  int idle_timeout_ms = 10'000;  // close a connection without a request this long; 0 = never
  int frame_timeout_ms = 500;    // a request must be complete this long after its first byte, and
                                 // its reply taken by the client within as long again
  int evict_idle_ms = 1'000;     // when all slots are taken, a holder idle this long makes room
};
inline constexpr int kMaxTimeoutMs = 86'400'000;  // one day: the largest value the options take

// Listens on host:port (port 0: the kernel picks one; see port()). Throws std::runtime_error
// with the failing call and errno text.
class ModbusTcpServer {
 public:
  ModbusTcpServer(const std::string& host, std::uint16_t port, SharedState& shared, AmplifierLimits limits,
                  ModbusTcpOptions options = {});
  ~ModbusTcpServer();
  ModbusTcpServer(const ModbusTcpServer&) = delete;
  ModbusTcpServer& operator=(const ModbusTcpServer&) = delete;

  void start();
  void stop();  // joins every thread; idempotent
  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] const std::string& host() const { return host_; }
  [[nodiscard]] const ModbusStats& stats() const { return stats_; }

 private:
  struct Connection;
  void supervise();  // the acceptor thread: accepts, evicts, enforces the deadlines, joins ended clients
  void accept_one(std::uint64_t now_ns);
  int enforce_deadlines(std::uint64_t now_ns);  // returns the poll timeout until the next check (ms; -1: none)
  void reap();
  void client_loop(Connection& c);
  bool enter(Connection& c, int phase);  // false once the connection is being closed

  std::string host_;
  std::uint16_t port_ = 0;
  SharedState& shared_;
  AmplifierLimits limits_;
  ModbusTcpOptions options_;
  int listen_fd_ = -1;
  int wake_fd_ = -1;  // eventfd: stop() and ending clients wake the acceptor thread
  std::atomic<bool> stopping_{false};
  std::thread acceptor_;
  std::mutex mutex_;  // guards connections_ and every Connection's phase, reason, fd
  std::vector<std::unique_ptr<Connection>> connections_;
  ModbusStats stats_;
};

// RTU slave on a serial device ("/dev/ttyUSB0", baud, 8N1), unit id `unit`. A request must be
// complete within frame_timeout_ms plus the time a 256-byte frame takes at `baud` after its first
// byte; a silence of max(3.5 characters, 20 ms) inside a frame ends it as partial.
class ModbusRtuServer {
 public:
  ModbusRtuServer(const std::string& device, int baud, int unit, SharedState& shared, AmplifierLimits limits,
                  int frame_timeout_ms = ModbusTcpOptions{}.frame_timeout_ms);
  ~ModbusRtuServer();
  ModbusRtuServer(const ModbusRtuServer&) = delete;
  ModbusRtuServer& operator=(const ModbusRtuServer&) = delete;
  void start();
  void stop();
  [[nodiscard]] const ModbusStats& stats() const { return stats_; }

 private:
  void loop();
  void drain(int fd);  // discard bytes until the line is silent
  std::string device_;
  int baud_;
  int unit_;
  int frame_timeout_ms_;
  SharedState& shared_;
  AmplifierLimits limits_;
  void* ctx_ = nullptr;  // modbus_t
  std::atomic<bool> stopping_{false};
  std::thread thread_;
  ModbusStats stats_;
};

}  // namespace swum::emu
