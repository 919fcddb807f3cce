#include "sdo_server.h"

#include <stdexcept>

namespace swum::canopen {

SdoServer::SdoServer(ObjectDictionary& od, std::uint8_t node_id, std::int64_t timeout_ns)
    : od_(od), request_id_(0x600u + node_id), response_id_(0x580u + node_id), timeout_ns_(timeout_ns) {
  if (node_id < 1 || node_id > 127) throw std::invalid_argument("SDO server: node id outside 1..127");
  if (timeout_ns <= 0) throw std::invalid_argument("SDO server: timeout must be > 0");
}

bool SdoServer::receive(const protocol::CanFrame&, std::int64_t, protocol::CanFrame&) { return false; }

bool SdoServer::poll(std::int64_t, protocol::CanFrame&) { return false; }

void SdoServer::reset() { state_ = State::idle; }

}  // namespace swum::canopen
