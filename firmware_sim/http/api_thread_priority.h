// The HTTP API's threads yield to the real-time loop (docs/http-api.md "It never touches the
// real-time loop"): on a machine with as many busy threads as cores, the loop's wake-up must not
// wait for a stream's JSON or a recording's write. With --rt the threads started after the loop
// took SCHED_FIFO inherit it, where they would never be preempted by the loop (same priority):
// they go back to SCHED_OTHER first. Linux's setpriority on a thread id then sets that thread
// alone; nice 10 is about a tenth of a normal thread's share when they compete.
#pragma once

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace swum::emu {

inline constexpr int kApiThreadNice = 10;

// Lowers the calling thread once (later calls do nothing); a failure is reported once to stderr.
inline void lower_api_thread_priority() {
  thread_local bool done = false;
  if (done) return;
  done = true;
  const sched_param normal{};
  if (const int e = pthread_setschedparam(pthread_self(), SCHED_OTHER, &normal); e != 0) {
    static std::atomic<bool> reported{false};
    if (!reported.exchange(true))
      std::fprintf(stderr, "swum-emu: --http: pthread_setschedparam(SCHED_OTHER): %s\n", std::strerror(e));
  }
  if (setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), kApiThreadNice) != 0) {
    static std::atomic<bool> reported{false};
    if (!reported.exchange(true))
      std::fprintf(stderr, "swum-emu: --http: setpriority(nice %d): %s (API threads at normal priority)\n",
                   kApiThreadNice, std::strerror(errno));
  }
}

}  // namespace swum::emu
