#include "heartbeat.h"

namespace swum::canopen {

namespace {
constexpr std::int64_t kNsPerMs = 1'000'000;
constexpr std::uint8_t kMaxNodeId = 127;
}  // namespace

void HeartbeatProducer::configure(std::uint16_t period_ms) {
  period_ns_ = static_cast<std::int64_t>(period_ms) * kNsPerMs;
  next_due_ns_ = last_sent_ns_ + period_ns_;
}

void HeartbeatProducer::restart(std::int64_t now_ns) {
  last_sent_ns_ = now_ns;
  next_due_ns_ = now_ns + period_ns_;
}

void HeartbeatProducer::poll(std::int64_t now_ns, std::uint8_t node_id, NmtState state, FrameSink& out) {
  if (period_ns_ == 0 || now_ns < next_due_ns_) return;
  out.send(heartbeat_frame(node_id, state));
  last_sent_ns_ = now_ns;
  // On the period's grid while polls keep up; from now after a stall (no catching up).
  next_due_ns_ += period_ns_;
  if (next_due_ns_ <= now_ns) next_due_ns_ = now_ns + period_ns_;
}

SdoAbort check_consumer_entry(std::span<const std::uint32_t, 4> entries, std::size_t changed, std::uint32_t value) {
  if ((value >> 24) != 0) return SdoAbort::value_range;
  const std::uint8_t node = consumer_node(value);
  if (node == 0 || consumer_time_ms(value) == 0) return SdoAbort::none;
  if (node > kMaxNodeId) return SdoAbort::value_range;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (i != changed && consumer_node(entries[i]) == node && consumer_time_ms(entries[i]) != 0) {
      return SdoAbort::general_incompatibility;
    }
  }
  return SdoAbort::none;
}

void HeartbeatConsumer::configure(std::span<const std::uint32_t, kEntries> entries) {
  for (std::size_t i = 0; i < kEntries; ++i) {
    Watch& w = watches_[i];
    if (w.entry == entries[i]) continue;
    w = Watch{};
    w.entry = entries[i];
    if (consumer_node(w.entry) != 0) w.time_ns = static_cast<std::int64_t>(consumer_time_ms(w.entry)) * kNsPerMs;
  }
}

void HeartbeatConsumer::on_frame(const protocol::CanFrame& frame, std::int64_t now_ns) {
  if (frame.extended || frame.dlc != 1 || frame.id <= kHeartbeatBaseId || frame.id > kHeartbeatBaseId + kMaxNodeId) {
    return;
  }
  const auto node = static_cast<std::uint8_t>(frame.id - kHeartbeatBaseId);
  for (Watch& w : watches_) {
    if (w.time_ns == 0 || consumer_node(w.entry) != node) continue;
    w.watching = true;
    w.last_seen_ns = now_ns;
    w.state = frame.data[0];
  }
}

int HeartbeatConsumer::poll(std::int64_t now_ns) {
  for (Watch& w : watches_) {
    if (!w.watching || now_ns - w.last_seen_ns <= w.time_ns) continue;
    w.watching = false;
    return consumer_node(w.entry);
  }
  return 0;
}

}  // namespace swum::canopen
