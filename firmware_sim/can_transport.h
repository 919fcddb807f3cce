// CAN transport on the CanBus interface (SocketCanBus on a real bus, FakeCanBus in tests):
// a receive thread (kernel filters on the node's two command identifiers; decode, CRC, alive
// counter, ranges -> command queue or reject with a reason) and a transmit thread (telemetry
// frames at a fixed rate, heartbeat). Bus-off / ENOBUFS are counted and survived.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>

#include "amplifier.h"
#include "can_bus.h"
#include "can_protocol.h"
#include "telemetry.h"

namespace swum::emu {

struct CanTransportConfig {
  std::uint8_t node = 1;
  double telemetry_hz = 100.0;    // Status/Motion/Drive/LoopStats/Output frames
  double heartbeat_s = 1.0;       // 0 = no heartbeat
};

struct CanStats {
  std::atomic<std::uint64_t> rx_frames{0};
  std::atomic<std::uint64_t> accepted{0};
  std::atomic<std::uint64_t> rejected{0};
  std::atomic<std::uint64_t> tx_frames{0};
  std::atomic<std::uint64_t> tx_dropped{0};  // ENOBUFS / EAGAIN: queue full, frame dropped
  std::atomic<std::uint64_t> tx_errors{0};
  std::atomic<std::uint64_t> rx_errors{0};
  std::atomic<std::uint64_t> error_frames{0};
  std::atomic<std::uint64_t> bus_off{0};
};

class CanTransport {
 public:
  // `tx_bus` may be null: then `rx_bus` is used for both directions.
  CanTransport(std::unique_ptr<io::CanBus> rx_bus, std::unique_ptr<io::CanBus> tx_bus, CanTransportConfig config,
               SharedState& shared, AmplifierLimits limits);
  ~CanTransport();
  CanTransport(const CanTransport&) = delete;
  CanTransport& operator=(const CanTransport&) = delete;
  void start();
  void stop();
  [[nodiscard]] const CanStats& stats() const { return stats_; }

 private:
  void rx_loop();
  void tx_loop();
  void send(const io::CanFrame& frame);
  std::unique_ptr<io::CanBus> rx_bus_;
  std::unique_ptr<io::CanBus> tx_bus_;
  CanTransportConfig config_;
  can::Ids ids_;
  SharedState& shared_;
  AmplifierLimits limits_;
  std::atomic<bool> stopping_{false};
  std::thread rx_thread_, tx_thread_;
  CanStats stats_;
};

}  // namespace swum::emu
