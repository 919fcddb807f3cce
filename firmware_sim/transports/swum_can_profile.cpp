#include "transports/swum_can_profile.h"

#include <stdexcept>
#include <string>

namespace swum::emu {

namespace can = protocol::can;

namespace {

// A Command or Aux frame: decoded (length, reserved bits, CRC), its alive counter checked, then
// the command submitted; the counter moves on only for a command that was queued.
template <typename Frame>
Reason read_command(const io::CanFrame& frame, Reason (*decode)(const io::CanFrame&, Frame&), can::AliveCounter& alive,
                    const CanRxTime& time, CanNodePort& node) {
  Frame f;
  Reason reason = decode(frame, f);
  if (reason == Reason::none) reason = alive.check(f.alive, time.clock_ns);
  if (reason == Reason::none) {
    reason = node.submit(can::to_command(f));
    if (reason == Reason::none) alive.accept(f.alive, time.clock_ns);
  }
  return reason;
}

}  // namespace

SwumCanProfile::SwumCanProfile(SwumCanProfileConfig config)
    : ids_(can::ids_for_node(config.node)),
      filters_{io::CanFilter{ids_.command, io::kCanStandardIdMax, false},
               io::CanFilter{ids_.aux, io::kCanStandardIdMax, false},
               io::CanFilter{can::kSyncId, io::kCanStandardIdMax, false}},
      heartbeat_ns_(static_cast<std::int64_t>(config.heartbeat_s * 1e9)) {
  if (config.node < can::kMinNode || config.node > can::kMaxNode)
    throw std::invalid_argument("CAN node id must be " + std::to_string(can::kMinNode) + ".." +
                                std::to_string(can::kMaxNode));
}

CanRxResult SwumCanProfile::receive(const io::CanFrame& frame, const CanRxTime& time, CanNodePort& node) {
  if (frame.extended) return {};  // every swum identifier is standard
  Reason reason = Reason::none;
  if (frame.id == ids_.command) {
    reason = read_command<can::CommandFrame>(frame, can::decode_command, command_alive_, time, node);
  } else if (frame.id == ids_.aux) {
    reason = read_command<can::AuxFrame>(frame, can::decode_aux, aux_alive_, time, node);
  } else if (frame.id == can::kSyncId) {
    // A SYNC reaches the profile only on the wall clock (in lockstep the transport steps the
    // clock with it): refused, after its own checks.
    can::SyncFrame sync;
    reason = can::decode_sync(frame, sync);
    if (reason == Reason::none) reason = Reason::clock_not_external;
  } else {
    return {};  // not for us (the filters normally keep these out)
  }
  return {reason == Reason::none ? CanRxStatus::accepted : CanRxStatus::refused, reason};
}

void SwumCanProfile::send_telemetry(const Telemetry& t, const RejectSnapshot& rejects, CanSender& out) {
  out.send(can::encode_status(t, rejects, status_counter_.fetch_add(1, std::memory_order_relaxed), ids_.status));
  out.send(can::encode_motion(t, ids_.motion));
  out.send(can::encode_drive(t, ids_.drive));
  out.send(can::encode_loop_stats(t, ids_.loop_stats));
  out.send(can::encode_clock(t, ids_.clock));
  out.send(can::encode_electrical_a(t, ids_.electrical_a));
  out.send(can::encode_electrical_b(t, ids_.electrical_b));
  out.send(can::encode_output(t, ids_.output));  // last: it ends the set
}

void SwumCanProfile::send_periodic(std::int64_t now_ns, CanSender& out) {
  if (heartbeat_ns_ <= 0) return;
  if (!heartbeat_started_) {  // the first heartbeat goes out with the first telemetry set
    next_heartbeat_ns_ = now_ns;
    heartbeat_started_ = true;
  }
  if (now_ns < next_heartbeat_ns_) return;
  out.send(can::encode_heartbeat(ids_.heartbeat));
  next_heartbeat_ns_ += heartbeat_ns_;
  if (next_heartbeat_ns_ < now_ns) next_heartbeat_ns_ = now_ns + heartbeat_ns_;
}

}  // namespace swum::emu
