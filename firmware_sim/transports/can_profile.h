// The CAN profile seam: the frame set a node speaks, apart from the bus it speaks it on. A
// profile knows which identifiers it listens to, how it reads (decodes, checks, dispatches) a
// received frame, and which frames it sends with each set of actual values and on its own wall-
// clock schedule. The transport (can_transport.h) keeps everything else: the sockets and their
// threads, the receive timestamps, the statistics, the --record-can file, the scenario's
// communication faults (CommFaultGate, telemetry silence) and the lockstep clock (a CiA 301
// SYNC, identifier 0x080 in every profile, steps the emulated clock under --clock external).
// Today's profile is the swum frame set (swum_can_profile.h, docs/protocols.md); a CANopen
// CiA 301/402 profile (SDO replies, NMT, heartbeat, PDOs) goes behind the same interface.
//
// Every call is on a real-time path: a profile allocates nothing and throws nothing; a frame's
// fate is a status (CanRxResult), never an exception. A profile whose state both threads change
// (the CANopen node: its dictionary, NMT state) may hold one lock of its own around a call,
// bounded (one frame or one snapshot) and never while waiting on the loop. What a frame it
// hands the transport costs is the transport's (CanSender::send): without --record-can, a
// non-blocking bus send and no lock; with --record-can, also a mutex shared by the receive and
// transmit threads and a buffered fprintf of one line per frame (so one thread may wait for the
// other's write, and for write(2) when stdio's buffer fills). Threads: receive() runs on the
// transport's receive thread only, send_periodic() on its transmit thread only, send_telemetry()
// on one of the two for a whole run (transmit thread on the wall clock, receive thread at each
// SYNC in lockstep).
#pragma once

#include <cstdint>
#include <span>

#include "can_bus.h"
#include "core/amplifier.h"
#include "core/shared_state.h"

namespace swum::emu {

// Where a profile's frames go: the transport counts and records each one; a full transmit queue
// drops the frame (counted), a bus error is counted and reported. The bus send never waits for
// the bus (a refused send comes back with io::CanResult's text, which the bus built); under
// --record-can the frame's line is written under the recording's mutex (above).
class CanSender {
 public:
  virtual void send(const io::CanFrame& frame) = 0;

 protected:
  ~CanSender() = default;
};

// What a profile may do while it reads a received frame: answer on the bus (an SDO reply) and
// hand the node a command. submit() checks the command against the amplifier's limits, stamps it
// with the frame's receive time (Command::accepted_ns) and queues it: Reason::none when queued,
// else why not (queue_full is logged by the queue itself).
class CanNodePort : public CanSender {
 public:
  virtual Reason submit(Command command) = 0;

 protected:
  ~CanNodePort() = default;
};

// The times of a received frame.
struct CanRxTime {
  std::int64_t receive_ns = 0;  // receive time on CLOCK_MONOTONIC (monotonic_clock.h)
  // The node's clock for protocol timeouts (e.g. the alive counter's resynchronisation window):
  // emulated time in lockstep, so that whether a frame counts never depends on wall time; else
  // receive_ns.
  std::int64_t clock_ns = 0;
};

// What a received frame came to.
enum class CanRxStatus {
  accepted,  // a command queued, or a frame of the protocol handled (counted as accepted)
  refused,   // refused for `reason` (counted, and logged as the last reject)
  ignored,   // not this node's (the filters normally keep these out): not counted
};
struct CanRxResult {
  CanRxStatus status = CanRxStatus::ignored;
  Reason reason = Reason::none;
};

class CanProfile {
 public:
  virtual ~CanProfile() = default;
  // The frames this profile reads, as kernel receive filters; set when the transport is built
  // (and again when filters_generation() moves). Include the SYNC identifier for the lockstep
  // clock to see SYNC frames. Never the node's own frames: the transport receives on a socket of
  // its own, which the kernel's loopback hands every frame the node sends.
  [[nodiscard]] virtual std::span<const io::CanFilter> filters() const = 0;
  // Filters that move at run time (CANopen: a master changes PDO identifiers and consumed
  // heartbeats by SDO): the transport compares this number after each receive() and applies
  // filters() again when it changed. Only receive() may change the filters (one thread).
  [[nodiscard]] virtual std::uint64_t filters_generation() const { return 0; }
  // One received frame (not an error frame, and not a SYNC that steps the lockstep clock).
  virtual CanRxResult receive(const io::CanFrame& frame, const CanRxTime& time, CanNodePort& node) = 0;
  // The actual values: the frames of one telemetry period on the wall clock, or of one SYNC in
  // lockstep. Not called during a scenario's bus-off or telemetry silence.
  virtual void send_telemetry(const Telemetry& t, const RejectSnapshot& rejects, CanSender& out) = 0;
  // Frames on the profile's own wall-clock schedule (heartbeat): called every transmit period
  // with the monotonic time, except during a scenario's bus-off. Not recorded in lockstep, where
  // the recording is on emulated time.
  virtual void send_periodic(std::int64_t now_ns, CanSender& out) = 0;
  // How often send_periodic() runs: 0 = every telemetry period (--telemetry-hz); else this
  // interval, while send_telemetry() keeps the telemetry period.
  [[nodiscard]] virtual std::int64_t periodic_interval_ns() const { return 0; }
};

}  // namespace swum::emu
