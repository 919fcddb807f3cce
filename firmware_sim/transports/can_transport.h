// CAN transport on the CanBus interface (SocketCanBus on a real bus, FakeCanBus in tests):
// a receive thread (kernel filters on the identifiers the profile reads; the profile decodes and
// checks each frame -> command queue or reject with a reason) and a transmit thread (the
// profile's telemetry frames at a fixed rate, its heartbeat). What frames the node speaks is the
// CanProfile's (can_profile.h; the swum frame set by default); sockets, statistics, recording,
// the scenario's faults and the lockstep SYNC are this transport's, the same for every profile.
// Bus-off / ENOBUFS are counted and survived.
// A command's receive time (Command::accepted_ns, start of the loop's accept-to-effect latency)
// is the bus's receive timestamp (the kernel's SO_TIMESTAMPNS on SocketCAN, CLOCK_REALTIME)
// converted to CLOCK_MONOTONIC, so time spent queued in the kernel socket counts too.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "can_bus.h"
#include "core/amplifier.h"
#include "core/loop_statistics.h"
#include "core/shared_state.h"
#include "transports/can_profile.h"

namespace swum::emu {

struct CanTransportConfig {
  std::uint8_t node = 1;          // the swum profile's node id (constructor without a profile)
  double telemetry_hz = 100.0;    // telemetry sets a second (swum: Status/Motion/.../Output frames)
  double heartbeat_s = 1.0;       // the swum profile's heartbeat; 0 = no heartbeat
  std::uint32_t sync_ticks = 10;  // lockstep: ticks per SYNC (control cycle)
  // --record-can: every frame received and sent, in candump's log format (canplayer replays
  // it); null: none. Owned by the caller, open for the transport's life.
  std::FILE* can_log = nullptr;
};

// Where a received frame's time came from.
enum class RxStampSource { bus, missing, implausible };
struct RxStamp {
  std::int64_t monotonic_ns = 0;  // receive time on CLOCK_MONOTONIC
  std::int64_t age_ns = 0;        // bus timestamp -> now (0 unless source == bus)
  RxStampSource source = RxStampSource::missing;
};
// Converts a frame's CLOCK_REALTIME receive timestamp to CLOCK_MONOTONIC with two clock readings
// taken now: monotonic_now - (realtime_now - timestamp). A zero timestamp is `missing`; an age
// below -1 ms or above 60 s (the realtime clock was stepped meanwhile) is `implausible`; both
// give monotonic_now. An age in [-1 ms, 0) (reading jitter) counts as 0.
RxStamp receive_time(std::chrono::nanoseconds timestamp, std::int64_t realtime_now_ns, std::int64_t monotonic_now_ns);
inline constexpr std::int64_t kMaxFrameAgeNs = 60'000'000'000;

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
  std::atomic<std::uint64_t> syncs{0};              // SYNC frames that stepped a cycle (lockstep)
  std::atomic<std::uint64_t> bus_off_discarded{0};  // frames received during an emulated bus-off (scenario)
  // Receive timestamps of the frames counted in rx_frames, by source (see receive_time()).
  std::atomic<std::uint64_t> rx_stamped{0};
  std::atomic<std::uint64_t> rx_stamp_missing{0};
  std::atomic<std::uint64_t> rx_stamp_implausible{0};
};

class CanTransport {
 public:
  // `tx_bus` may be null: then `rx_bus` is used for both directions. Speaks the swum frame set
  // (SwumCanProfile) as node config.node. Throws std::invalid_argument for a bad node id,
  // std::runtime_error when the receive filters cannot be set.
  CanTransport(std::unique_ptr<io::CanBus> rx_bus, std::unique_ptr<io::CanBus> tx_bus, CanTransportConfig config,
               SharedState& shared, AmplifierLimits limits);
  // The same with any frame set; config.node and config.heartbeat_s are then unused.
  CanTransport(std::unique_ptr<io::CanBus> rx_bus, std::unique_ptr<io::CanBus> tx_bus,
               std::unique_ptr<CanProfile> profile, CanTransportConfig config, SharedState& shared,
               AmplifierLimits limits);
  ~CanTransport();
  CanTransport(const CanTransport&) = delete;
  CanTransport& operator=(const CanTransport&) = delete;
  void start();
  void stop();
  [[nodiscard]] const CanStats& stats() const { return stats_; }
  // Bus receive timestamp -> the receive thread read the frame (time queued in the kernel
  // socket + wake-up), per frame with a usable timestamp. Written by the receive thread: read
  // it only after stop().
  [[nodiscard]] const Histogram& receive_age() const { return receive_age_; }

 private:
  class Port;  // the CanNodePort / CanSender the profile is handed
  void rx_loop();
  void tx_loop();
  void send(const io::CanFrame& frame, bool record);  // record: into --record-can
  void send_telemetry();                              // the profile's frames of the latest snapshot
  Reason on_sync(const io::CanFrame& frame);          // lockstep: telemetry sampled now, then one cycle
  void log_frame(const io::CanFrame& frame);          // --record-can
  std::mutex log_mutex_;
  std::unique_ptr<io::CanBus> rx_bus_;
  std::unique_ptr<io::CanBus> tx_bus_;
  std::unique_ptr<CanProfile> profile_;
  std::string bus_name_;  // the recording's IFACE field, read once (name() returns a new string)
  CanTransportConfig config_;
  SharedState& shared_;
  AmplifierLimits limits_;
  std::atomic<bool> stopping_{false};
  std::thread rx_thread_, tx_thread_;
  CanStats stats_;
  Histogram receive_age_;
  std::uint64_t filters_generation_ = 0;  // receive thread: the profile's filters last applied
};

}  // namespace swum::emu
