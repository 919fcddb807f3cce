// The swum CAN frame set (docs/protocols.md, config/swum.dbc) as a CanProfile: Command and Aux
// frames in (length, reserved bits, CRC-8, alive counter, ranges -> a command or a refusal with
// its reason), the telemetry set Status/Motion/Drive/LoopStats/Clock/ElectricalA/ElectricalB/
// Output out at each telemetry period or SYNC, and the heartbeat. The codecs are protocol/'s.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "can_codec.h"
#include "transports/can_profile.h"

namespace swum::emu {

struct SwumCanProfileConfig {
  std::uint8_t node = 1;     // protocol::can::kMinNode..kMaxNode: the identifiers (ids_for_node)
  double heartbeat_s = 1.0;  // 0 = no heartbeat
};

class SwumCanProfile final : public CanProfile {
 public:
  // Throws std::invalid_argument for a node id out of range (load time).
  explicit SwumCanProfile(SwumCanProfileConfig config);

  [[nodiscard]] std::span<const io::CanFilter> filters() const override { return filters_; }
  CanRxResult receive(const io::CanFrame& frame, const CanRxTime& time, CanNodePort& node) override;
  void send_telemetry(const Telemetry& t, const RejectSnapshot& rejects, CanSender& out) override;
  void send_periodic(std::int64_t now_ns, CanSender& out) override;
  [[nodiscard]] const protocol::can::Ids& ids() const { return ids_; }

 private:
  protocol::can::Ids ids_;
  std::array<io::CanFilter, 3> filters_;
  std::int64_t heartbeat_ns_;
  // Receive thread: each command frame kind has its own alive counter.
  protocol::can::AliveCounter command_alive_, aux_alive_;
  // The Status frame's running count: atomic, as send_telemetry() may run on either thread.
  std::atomic<std::uint8_t> status_counter_{0};
  // Transmit thread: the next heartbeat (set at the first call).
  std::int64_t next_heartbeat_ns_ = 0;
  bool heartbeat_started_ = false;
};

}  // namespace swum::emu
