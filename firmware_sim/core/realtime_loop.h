// The fixed-step real-time loop: the only code of the emulator that reads the clock.
// CLOCK_MONOTONIC, absolute deadlines (clock_nanosleep TIMER_ABSTIME), one EmulatorCore::tick()
// per period. --speedup K shortens the wall period by K (K = 0: as fast as possible) with the
// same tick semantics (the model and the watchdog count ticks, not wall time).
#pragma once

#include <atomic>
#include <cstdint>
#include <string>

#include "core/emulator_core.h"
#include "core/loop_statistics.h"

namespace swum::emu {

struct LoopConfig {
  double speedup = 1.0;         // wall period = tick period / speedup; 0 = free-running
  std::uint64_t max_ticks = 0;  // 0 = until stop
  bool realtime = false;        // try SCHED_FIFO + mlockall
  int priority = 80;
  std::uint64_t stats_every_ticks = 1000;
  // Ticks later than this behind schedule are dropped from the schedule (deadline resync),
  // counted in resyncs; the emulated time still advances one tick per tick.
  double resync_after_s = 0.1;
  // Sleep until this long before each deadline, then spin on the clock: the wake-up of a
  // sleeping thread (timer interrupt, and on a VM the host scheduling the idle vCPU again)
  // costs tens of microseconds to milliseconds; a spinning CPU is already running.
  // 0 = sleep all the way (no busy CPU). Costs up to spin/period of one CPU.
  double spin_s = 0.0;
};

// Outcome of the SCHED_FIFO / mlockall attempt (a message, never a failure).
std::string try_realtime(int priority);

class RealtimeLoop {
 public:
  RealtimeLoop(EmulatorCore& core, LoopConfig config);
  // Runs until `stop` is set or max_ticks are done. Returns the number of ticks run.
  std::uint64_t run(const std::atomic<bool>& stop);

  [[nodiscard]] const LoopStatistics& statistics() const { return stats_; }
  [[nodiscard]] std::uint64_t resyncs() const { return resyncs_; }
  [[nodiscard]] double wall_seconds() const { return wall_s_; }

 private:
  EmulatorCore& core_;
  LoopConfig config_;
  LoopStatistics stats_;
  std::uint64_t resyncs_ = 0;
  double wall_s_ = 0.0;
  bool sleep_error_reported_ = false;
};

}  // namespace swum::emu
