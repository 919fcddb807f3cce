// CLOCK_MONOTONIC in nanoseconds: the one clock the loop's deadlines, the transports' deadlines
// and Command::accepted_ns (set by a transport, read by the loop for the accept-to-effect latency)
// are all measured on, so they compare across threads. Inline: it is on every real-time path and
// is one vDSO call; no allocation, no throw, no lock.
#pragma once

#include <time.h>

#include <cstdint>

namespace swum::emu {

inline std::int64_t monotonic_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);  // cannot fail for CLOCK_MONOTONIC with a valid pointer
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// A time on that clock (nanoseconds, not negative) as clock_nanosleep(CLOCK_MONOTONIC,
// TIMER_ABSTIME, ...) takes it.
inline timespec to_timespec(std::int64_t ns) noexcept {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
  return ts;
}

}  // namespace swum::emu
