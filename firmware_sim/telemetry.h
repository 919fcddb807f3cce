// What the loop publishes once per tick (Seqlock<Telemetry>) and what the transports share
// with it: the command queue and the reject log.
#pragma once

#include <atomic>
#include <cstdint>

#include "amplifier.h"
#include "lockfree.h"
#include "loop_statistics.h"

namespace swum::emu {

struct Telemetry {
  std::uint64_t tick = 0;
  double sim_time_s = 0.0;
  AmpState state = AmpState::disabled;
  FaultCode fault = FaultCode::none;
  bool enable_line = true;
  bool at_setpoint = true;
  AmplifierSetpoints setpoints;
  DriveInput output;                 // what the amplifier drives this tick
  double speed_m_s = 0.0;            // mover speed, mean over the last speed window (10 ms)
  double tick_speed_m_s = 0.0;       // mean over the last tick
  double position_m = 0.0;
  double tip_normal_um = 0.0;        // (max - min)/2 of u_tip over the last tick
  double tip_tangential_um = 0.0;    // (max - min)/2 of w_tip over the last tick
  std::uint64_t applied_commands = 0;
  std::uint64_t amplifier_rejects = 0;
  std::uint64_t last_sequence = 0;   // sequence of the last command applied
  std::uint64_t divergences = 0;
  LoopStatsSummary stats;            // refreshed about 10 times per second
};

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

// Everything the loop and the transports share. Lives for the whole process.
struct SharedState {
  CommandQueue commands;
  Seqlock<Telemetry> telemetry;
  RejectLog rejects;
  std::atomic<bool> enable_line{true};        // GPIO transport -> loop
  std::atomic<std::uint64_t> next_sequence{1};
  std::atomic<std::uint64_t> queue_full{0};

  // Validates and queues a command. Returns Reason::none when accepted (it will be applied, in
  // order, at the next tick boundary); otherwise records the reason and returns it.
  Reason submit(Command command);
};

}  // namespace swum::emu
