// Modbus transports on libmodbus: a TCP server (one thread accepting, one thread per client,
// up to max_clients at once) and an RTU server on a serial device (one thread). Requests are
// checked by register_map (pure); accepted writes go to the command queue, reads are served
// from the latest telemetry snapshot. The loop never waits for these threads.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "amplifier.h"
#include "telemetry.h"

namespace swum::emu {

struct ModbusStats {
  std::atomic<std::uint64_t> requests{0};
  std::atomic<std::uint64_t> exceptions{0};
  std::atomic<std::uint64_t> connections{0};
  std::atomic<std::uint64_t> refused_connections{0};
  std::atomic<std::uint64_t> receive_errors{0};
};

// Listens on host:port (port 0: the kernel picks one; see port()). Throws std::runtime_error
// with the failing call and errno text.
class ModbusTcpServer {
 public:
  ModbusTcpServer(const std::string& host, std::uint16_t port, SharedState& shared, AmplifierLimits limits,
                  int max_clients = 16);
  ~ModbusTcpServer();
  ModbusTcpServer(const ModbusTcpServer&) = delete;
  ModbusTcpServer& operator=(const ModbusTcpServer&) = delete;

  void start();
  void stop();  // joins every thread; idempotent
  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] const std::string& host() const { return host_; }
  [[nodiscard]] const ModbusStats& stats() const { return stats_; }

 private:
  void accept_loop();
  void client_loop(int fd);

  std::string host_;
  std::uint16_t port_ = 0;
  SharedState& shared_;
  AmplifierLimits limits_;
  int max_clients_;
  int listen_fd_ = -1;
  int wake_fd_ = -1;  // eventfd: stop() wakes the accept thread
  std::atomic<bool> stopping_{false};
  std::thread acceptor_;
  std::mutex mutex_;
  std::vector<int> client_fds_;
  std::vector<std::thread> clients_;
  std::atomic<int> active_{0};
  ModbusStats stats_;
};

// RTU slave on a serial device ("/dev/ttyUSB0", baud, 8N1), unit id `unit`.
class ModbusRtuServer {
 public:
  ModbusRtuServer(const std::string& device, int baud, int unit, SharedState& shared, AmplifierLimits limits);
  ~ModbusRtuServer();
  ModbusRtuServer(const ModbusRtuServer&) = delete;
  ModbusRtuServer& operator=(const ModbusRtuServer&) = delete;
  void start();
  void stop();
  [[nodiscard]] const ModbusStats& stats() const { return stats_; }

 private:
  void loop();
  std::string device_;
  SharedState& shared_;
  AmplifierLimits limits_;
  void* ctx_ = nullptr;  // modbus_t
  std::atomic<bool> stopping_{false};
  std::thread thread_;
  ModbusStats stats_;
};

// Parses "tcp://HOST:PORT" or "rtu:/dev/DEVICE:BAUD". Returns an error text, empty when fine.
struct ModbusEndpoint {
  bool tcp = true;
  std::string host = "127.0.0.1";
  std::uint16_t port = 1502;
  std::string device;
  int baud = 115200;
};
std::string parse_modbus_endpoint(const std::string& text, ModbusEndpoint& out);

}  // namespace swum::emu
