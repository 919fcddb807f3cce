// The heartbeat of CiA 301's error control (7.2.8): this node's producer (0x1017, every
// period a frame 0x700 + node with its NMT state) and its consumer (0x1016, up to four other nodes
// watched, each with a time after which its heartbeat counts as lost). Pure: times are passed in.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "can_frame.h"
#include "frame_sink.h"
#include "nmt.h"
#include "object_dictionary.h"

namespace swum::canopen {

class HeartbeatProducer {
 public:
  // 0x1017 in ms; 0 disables. A change takes effect from the last heartbeat (or restart).
  void configure(std::uint16_t period_ms);
  // The boot-up frame just sent counts as the first heartbeat: the next is one period later.
  void restart(std::int64_t now_ns);
  // Sends the heartbeat when it is due. After a stall longer than a period it sends one frame
  // and resumes one period later (a master watching us sees a late heartbeat, not a burst).
  void poll(std::int64_t now_ns, std::uint8_t node_id, NmtState state, FrameSink& out);

 private:
  std::int64_t period_ns_ = 0;
  std::int64_t last_sent_ns_ = 0;
  std::int64_t next_due_ns_ = 0;
};

// One sub-index 1-4 of 0x1016: bits 16-23 the node, bits 0-15 the time in ms (7.5.2.19).
inline constexpr std::uint8_t consumer_node(std::uint32_t entry) { return static_cast<std::uint8_t>(entry >> 16); }
inline constexpr std::uint16_t consumer_time_ms(std::uint32_t entry) { return static_cast<std::uint16_t>(entry); }

// The write check a WriteObserver of 0x1016 sub 1-4 makes (the profile installs it): `value` for
// entries[changed] (0-based: sub-index changed + 1). Refused: reserved bits 24-31 set, or a node
// id above 127 while the time is not 0 (value_range); the same node already watched by another
// entry with a time not 0 (general_incompatibility, 7.5.2.19: "0604 0043h"). Otherwise an entry
// with node 0 or time 0 is unused and accepted. (ObjectDictionary::write makes the same check.)
SdoAbort check_consumer_entry(std::span<const std::uint32_t, 4> entries, std::size_t changed, std::uint32_t value);

class HeartbeatConsumer {
 public:
  static constexpr std::size_t kEntries = 4;

  // The four values of 0x1016 sub 1-4. An entry whose value changed starts over (not watched
  // until its node's next heartbeat); an unchanged one keeps its state.
  void configure(std::span<const std::uint32_t, kEntries> entries);
  // A heartbeat (or boot-up) frame of a watched node: 0x700 + node, one byte. The first one
  // starts the monitoring of that node (7.2.8); frames of other lengths are ignored.
  void on_frame(const protocol::CanFrame& frame, std::int64_t now_ns);
  // The node whose heartbeat has been missing longer than its time, 0 if none: each loss is
  // reported once (one node per call), and that node is not watched again until its next heartbeat.
  int poll(std::int64_t now_ns);
  // The state the node's last heartbeat carried (initialising for a boot-up or none seen yet).
  [[nodiscard]] std::uint8_t last_state(std::size_t entry) const { return watches_[entry].state; }

 private:
  struct Watch {
    std::uint32_t entry = 0;
    std::int64_t time_ns = 0;  // 0: unused
    std::int64_t last_seen_ns = 0;
    bool watching = false;  // a heartbeat seen and not lost since
    std::uint8_t state = 0;
  };
  std::array<Watch, kEntries> watches_{};
};

}  // namespace swum::canopen
