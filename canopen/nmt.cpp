#include "nmt.h"

namespace swum::canopen {

namespace {
bool known(std::uint8_t specifier) {
  switch (static_cast<NmtCommand>(specifier)) {
    case NmtCommand::start:
    case NmtCommand::stop:
    case NmtCommand::enter_pre_operational:
    case NmtCommand::reset_node:
    case NmtCommand::reset_communication: return true;
  }
  return false;
}

protocol::CanFrame one_byte_frame(std::uint8_t node_id, std::uint8_t byte) {
  protocol::CanFrame frame;
  frame.id = kHeartbeatBaseId + node_id;
  frame.dlc = 1;
  frame.data[0] = byte;
  return frame;
}
}  // namespace

NmtDecode decode_nmt(const protocol::CanFrame& frame, std::uint8_t node_id, NmtCommand& command) {
  if (frame.extended || frame.id != kNmtId) return NmtDecode::not_for_us;
  // Checked before the address: a broken NMT frame is counted whichever node it names.
  if (frame.dlc != 2 || !known(frame.data[0])) return NmtDecode::malformed;
  const std::uint8_t addressed = frame.data[1];
  if (addressed != 0 && addressed != node_id) return NmtDecode::not_for_us;
  command = static_cast<NmtCommand>(frame.data[0]);
  return NmtDecode::for_us;
}

NmtState next_state(NmtState state, NmtCommand command) {
  if (command == NmtCommand::reset_node || command == NmtCommand::reset_communication) {
    return NmtState::initialising;
  }
  if (state == NmtState::initialising) return state;
  switch (command) {
    case NmtCommand::start: return NmtState::operational;
    case NmtCommand::stop: return NmtState::stopped;
    case NmtCommand::enter_pre_operational: return NmtState::pre_operational;
    default: return state;
  }
}

protocol::CanFrame boot_up_frame(std::uint8_t node_id) { return one_byte_frame(node_id, 0x00); }

protocol::CanFrame heartbeat_frame(std::uint8_t node_id, NmtState state) {
  return one_byte_frame(node_id, static_cast<std::uint8_t>(state));
}

const char* to_string(NmtState state) {
  switch (state) {
    case NmtState::initialising: return "initialising";
    case NmtState::stopped: return "stopped";
    case NmtState::operational: return "operational";
    case NmtState::pre_operational: return "pre-operational";
  }
  return "unknown";
}

const char* to_string(NmtCommand command) {
  switch (command) {
    case NmtCommand::start: return "start";
    case NmtCommand::stop: return "stop";
    case NmtCommand::enter_pre_operational: return "enter pre-operational";
    case NmtCommand::reset_node: return "reset node";
    case NmtCommand::reset_communication: return "reset communication";
  }
  return "unknown";
}

bool sdo_allowed(NmtState state) { return state == NmtState::pre_operational || state == NmtState::operational; }
bool pdo_allowed(NmtState state) { return state == NmtState::operational; }
bool emcy_allowed(NmtState state) { return sdo_allowed(state); }
bool sync_allowed(NmtState state) { return sdo_allowed(state); }

}  // namespace swum::canopen
