// Network management (CiA 301 7.2.8): the NMT node control command a master sends on identifier
// 0x000, the NMT state machine it drives (7.3.2), the boot-up and heartbeat frames of
// the error control protocols (7.2.8), and which communication objects each state allows
// (Table 83). Pure: the caller keeps the state and does what a transition asks (a reset resets
// the dictionary, sends the boot-up frame and enters pre-operational).
#pragma once

#include <cstdint>

#include "can_frame.h"

namespace swum::canopen {

// The state's code as the heartbeat carries it (heartbeat protocol, 7.2.8).
enum class NmtState : std::uint8_t { initialising = 0x00, stopped = 0x04, operational = 0x05, pre_operational = 0x7F };

// The command specifier of the node control protocol (7.2.8).
enum class NmtCommand : std::uint8_t {
  start = 0x01,
  stop = 0x02,
  enter_pre_operational = 0x80,
  reset_node = 0x81,
  reset_communication = 0x82
};

inline constexpr std::uint32_t kNmtId = 0x000;
inline constexpr std::uint32_t kHeartbeatBaseId = 0x700;  // + node id: boot-up and heartbeat

// for_us: a command addressed to node_id or to all nodes (node 0), in `command`. not_for_us: not
// an NMT frame (another identifier, a 29-bit frame) or a command for another node. malformed: an
// NMT frame whose length is not 2 or whose command specifier is unknown (counted by the caller).
enum class NmtDecode { for_us, not_for_us, malformed };
NmtDecode decode_nmt(const protocol::CanFrame& frame, std::uint8_t node_id, NmtCommand& command);

// The state a command leads to (the NMT state diagram of 7.3.2). Both resets lead to
// initialising, from which the caller, once it has reset, sends the boot-up frame and enters
// pre_operational; initialising itself ignores start, stop and enter pre-operational (the node is
// not yet on the bus).
NmtState next_state(NmtState state, NmtCommand command);

// 0x700 + node, one byte 0x00 (boot-up protocol, 7.2.8).
protocol::CanFrame boot_up_frame(std::uint8_t node_id);
// 0x700 + node, one byte: the state's code (heartbeat protocol, 7.2.8).
protocol::CanFrame heartbeat_frame(std::uint8_t node_id, NmtState state);

const char* to_string(NmtState state);  // "initialising", "stopped", "operational", "pre-operational"
const char* to_string(NmtCommand command);

// Table 83: SDO in pre-operational and operational; PDO in operational only; EMCY and SYNC
// (consumed) in pre-operational and operational; NMT and heartbeat in every state but
// initialising (the boot-up frame is its only message).
bool sdo_allowed(NmtState state);
bool pdo_allowed(NmtState state);
bool emcy_allowed(NmtState state);
bool sync_allowed(NmtState state);

}  // namespace swum::canopen
