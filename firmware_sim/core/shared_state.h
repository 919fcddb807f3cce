// What the loop and the transports share: the per-tick telemetry snapshot (a Seqlock of the
// protocol's Telemetry), the command queue and the reject log.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "core/amplifier.h"
#include "core/comm_fault_gate.h"
#include "core/drive_request.h"
#include "core/lockfree.h"
#include "core/scenario.h"
#include "telemetry.h"

namespace swum::emu {

// The per-tick snapshot is the protocol's telemetry value (protocol/telemetry.h): what the
// interfaces encode is exactly what the loop publishes.
using protocol::RejectSnapshot;
using protocol::Telemetry;

// Last reject reason and counts, written by any thread (transports and the loop).
struct RejectLog {
  std::atomic<std::uint8_t> last_reason{0};
  std::atomic<std::uint8_t> last_source{0};
  std::atomic<std::uint64_t> count{0};
  void record(Reason reason, CommandSource source) {
    last_reason.store(static_cast<std::uint8_t>(reason), std::memory_order_relaxed);
    last_source.store(static_cast<std::uint8_t>(source), std::memory_order_relaxed);
    count.fetch_add(1, std::memory_order_release);
  }
};

inline constexpr std::size_t kCommandQueueCapacity = 1024;
using CommandQueue = BoundedQueue<Command, kCommandQueueCapacity>;

// A fault started or cleared at run time (the HTTP API, docs/http-api.md): queued by the API's
// threads, started by the loop at the next tick boundary exactly like a scenario's event.
// `clear` with parameters.fault == EventType::clear ends every fault in force.
struct RuntimeEvent {
  EventType type = EventType::clear;
  EventParameters parameters;
};
inline constexpr std::size_t kRuntimeEventCapacity = 64;
using RuntimeEventQueue = BoundedQueue<RuntimeEvent, kRuntimeEventCapacity>;

// The faults in force (scenario and run time), published by the loop when they change.
inline constexpr std::size_t kMaxActiveFaults = 32;
struct ActiveFault {
  EventType type = EventType::clear;
  std::uint64_t since_tick = 0;
  std::uint64_t until_tick = 0;  // 0: until cleared
  EventParameters parameters;
};
struct ActiveFaults {
  std::uint64_t generation = 0;  // changes with every change of the set
  std::uint32_t count = 0;       // listed in items (the first kMaxActiveFaults)
  std::uint32_t total = 0;       // in force (a scenario's faults may be more than items holds)
  // Run-time events refused by the loop: not faults, more than kRuntimeEventCapacity in one
  // tick, or kMaxActiveFaults run-time faults already in force.
  std::uint64_t refused = 0;
  std::array<ActiveFault, kMaxActiveFaults> items{};
};

// The telemetry of every tick while a recording runs (the HTTP API's recording): the loop
// pushes, the API's writer thread drains into a file. A full ring drops the tick and counts it.
inline constexpr std::size_t kRecordingRingCapacity = 16384;  // 1.6 s at 10 kHz
struct TelemetryRecording {
  std::atomic<bool> on{false};
  BoundedQueue<Telemetry, kRecordingRingCapacity> ring;
  std::atomic<std::uint64_t> dropped{0};
};

// Everything the loop and the transports share. Lives for the whole process.
class LockstepClock;

struct SharedState {
  CommandQueue commands;
  LockstepClock* lockstep = nullptr;  // --clock external: who asks for ticks; nullptr: wall time
  Seqlock<Telemetry> telemetry;
  // The CiA 402 drive's inputs: stored by the CANopen profile, loaded by the loop once per tick.
  Seqlock<DriveRequest> drive_request;
  // The CANopen profile's NMT state (canopen::NmtState's value), for the HTTP API and the
  // dashboard; kNoCanopen when the node speaks no CANopen.
  static constexpr std::uint8_t kNoCanopen = 0xFF;
  std::atomic<std::uint8_t> canopen_nmt_state{kNoCanopen};
  RejectLog rejects;
  std::atomic<bool> enable_line{true};  // GPIO transport -> loop
  std::atomic<std::uint64_t> next_sequence{1};
  std::atomic<std::uint64_t> queue_full{0};

  // Communication faults of a scenario (docs/scenarios.md): set by the loop at tick boundaries,
  // read by the transports for each request / frame. Each transport has its own gate.
  std::atomic<bool> telemetry_silent{false};  // no telemetry out (Modbus FC04 unanswered, no CAN frames)
  CommFaultGate modbus_faults;                // modbus_drop, modbus_delay
  CommFaultGate can_faults;                   // can_bus_off
  // The HTTP API (off unless --http): run-time faults in, the faults in force out, the recording.
  RuntimeEventQueue runtime_events;
  Seqlock<ActiveFaults> active_faults;
  TelemetryRecording* recording = nullptr;  // owned by the API; nullptr: no recording possible
  double speedup = 1.0;    // emulated per wall second (wall-time delays); set before the transports start
  double tick_hz = 1.0e4;  // ticks per emulated second (lockstep delays); set before the transports start

  // Validates and queues a command. Returns Reason::none when accepted (it will be applied, in
  // order, at the next tick boundary); otherwise records the reason and returns it.
  Reason submit(Command command);
};

}  // namespace swum::emu
