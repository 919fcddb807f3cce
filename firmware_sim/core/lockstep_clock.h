// Lockstep (--clock external): emulated time belongs to the controller. The transports ask for
// ticks (a Modbus write of the advance register, a CAN SYNC) and wait until they have run; the
// loop thread runs exactly the ticks asked for, as fast as the CPU allows, and nothing depends on
// the host clock (docs/emulator.md, "Lockstep"). As with PX4's lockstep or an FMI doStep: the
// same inputs give the same trace.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>

#include "core/emulator_core.h"

namespace swum::emu {

// Requests of ticks from any number of transport threads, served in the order they came.
class LockstepClock {
 public:
  // Transport side: run `ticks` more ticks (after every command this thread queued before the
  // call) and wait until they are done. False when the emulator stops first (the ticks are not
  // all run: --duration-s reached, SIGTERM).
  bool advance(std::uint64_t ticks);

  // Loop side: wait until more ticks are asked for than `done`; the total asked for so far, or 0
  // when `stop` was set or close() called. Polls `stop` every 50 ms (set by the signal thread).
  std::uint64_t wait_for_request(std::uint64_t done, const std::atomic<bool>& stop);
  // Loop side: `done` ticks have run in all (wakes the transports waiting for them).
  void completed(std::uint64_t done);
  // No more ticks will run: every waiting and later advance() returns false.
  void close();

  [[nodiscard]] std::uint64_t requested() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable requested_cv_;
  std::condition_variable completed_cv_;
  std::uint64_t requested_ = 0;  // ticks asked for since the start, in all
  std::uint64_t completed_ = 0;  // ticks run since the start
  bool closed_ = false;
};

struct LockstepConfig {
  std::uint64_t max_ticks = 0;  // --duration-s; 0 = until stop
};

// The loop of the external clock: runs EmulatorCore::tick() only for ticks asked for. Loop timing
// figures stay zero in the telemetry (they would differ from run to run).
class LockstepLoop {
 public:
  LockstepLoop(EmulatorCore& core, LockstepClock& clock, LockstepConfig config);
  // Until `stop`, or max_ticks run. Returns the number of ticks run. Closes the clock when it ends.
  std::uint64_t run(const std::atomic<bool>& stop);
  [[nodiscard]] double wall_seconds() const { return wall_s_; }

 private:
  EmulatorCore& core_;
  LockstepClock& clock_;
  LockstepConfig config_;
  double wall_s_ = 0.0;
};

}  // namespace swum::emu
