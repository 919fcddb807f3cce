#include "core/realtime_loop.h"

#include "core/monotonic_clock.h"

#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <time.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace swum::emu {

std::string try_realtime(int priority) {
  std::string message;
  sched_param param{};
  param.sched_priority = priority;
  if (sched_setscheduler(0, SCHED_FIFO, &param) != 0) {
    const int e = errno;
    message += "SCHED_FIFO not available (sched_setscheduler: " + std::string(std::strerror(e)) +
               "); running with the default scheduler";
  } else {
    message += "SCHED_FIFO priority " + std::to_string(priority);
  }
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    const int e = errno;
    message += "; mlockall failed (" + std::string(std::strerror(e)) + "), memory not locked";
  } else {
    message += "; memory locked (mlockall)";
  }
  return message;
}

RealtimeLoop::RealtimeLoop(EmulatorCore& core, LoopConfig config) : core_(core), config_(config) {}

std::uint64_t RealtimeLoop::run(const std::atomic<bool>& stop) {
  const bool free_running = !(config_.speedup > 0.0);
  const auto period_ns = free_running ? std::int64_t{0}
                                      : static_cast<std::int64_t>(core_.tick_s() * 1e9 / config_.speedup);
  const auto resync_ns = static_cast<std::int64_t>(config_.resync_after_s * 1e9);
  // Timer slack (50 us by default for SCHED_OTHER) would delay every wake-up: ask for 1 ns.
  if (prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL) != 0)
    std::fprintf(stderr, "swum-emu: prctl(PR_SET_TIMERSLACK): %s\n", std::strerror(errno));
  const std::int64_t start = monotonic_ns();
  std::int64_t deadline = start + period_ns;
  std::uint64_t ticks = 0;
  while (!stop.load(std::memory_order_relaxed) && (config_.max_ticks == 0 || ticks < config_.max_ticks)) {
    std::int64_t wake = 0;
    if (!free_running) {
      const std::int64_t spin_ns = static_cast<std::int64_t>(config_.spin_s * 1e9);
      const timespec ts = to_timespec(deadline - spin_ns);
      int rc;
      while ((rc = clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr)) == EINTR) {
        if (stop.load(std::memory_order_relaxed)) break;
      }
      if (rc != 0 && rc != EINTR && !sleep_error_reported_) {  // returns the error, not errno
        std::fprintf(stderr, "swum-emu: clock_nanosleep: %s\n", std::strerror(rc));
        sleep_error_reported_ = true;
      }
      wake = monotonic_ns();
      while (spin_ns > 0 && wake < deadline && !stop.load(std::memory_order_relaxed)) wake = monotonic_ns();
    } else {
      wake = monotonic_ns();
      deadline = wake;
    }
    const std::int64_t lateness = wake - deadline;
    core_.tick();
    for (const std::uint64_t accepted : core_.accepted_in_last_tick()) {
      const std::int64_t delay = wake - static_cast<std::int64_t>(accepted);
      stats_.record_command_latency(static_cast<std::uint64_t>(delay > 0 ? delay : 0));
    }
    ++ticks;
    if (config_.stats_every_ticks && ticks % config_.stats_every_ticks == 0) core_.set_stats(stats_.summary());
    const std::int64_t end = monotonic_ns();
    const bool overrun = !free_running && end > deadline + period_ns;
    stats_.record(static_cast<std::uint64_t>(lateness > 0 ? lateness : 0), static_cast<std::uint64_t>(end - wake),
                  overrun);
    deadline += period_ns;
    if (!free_running && end - deadline > resync_ns) {
      deadline = end + period_ns;
      ++resyncs_;
    }
  }
  wall_s_ = static_cast<double>(monotonic_ns() - start) * 1e-9;
  core_.set_stats(stats_.summary());
  return ticks;
}

}  // namespace swum::emu
