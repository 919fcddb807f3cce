// Where the CANopen slave's parts put the frames they produce (boot-up, heartbeat, EMCY, TPDOs):
// the profile forwards them to the bus, a test collects them. Called on per-frame paths: an
// implementation neither allocates nor throws there.
#pragma once

#include "can_frame.h"

namespace swum::canopen {

class FrameSink {
 public:
  virtual void send(const protocol::CanFrame& frame) = 0;

 protected:
  ~FrameSink() = default;
};

}  // namespace swum::canopen
