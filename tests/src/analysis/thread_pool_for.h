// A ParallelFor for the model tests (src/ starts no threads; the host has its own): tasks
// strided over two threads.
#pragma once

#include <exception>
#include <functional>
#include <thread>

#include "analysis/steady_state/parallel_for.h"

namespace swum::test {

// Runs work(0) on this thread and work(1) on a second one, and returns when both are done. An
// exception from either is rethrown here once both have finished: thrown on a std::thread, or
// unwinding past one still joinable, it would terminate the whole test binary instead of
// failing one test.
inline void on_two_threads(const std::function<void(int which)>& work) {
  std::exception_ptr errors[2];
  std::thread other([&] {
    try {
      work(1);
    } catch (...) {
      errors[1] = std::current_exception();
    }
  });
  try {
    work(0);
  } catch (...) {
    errors[0] = std::current_exception();
  }
  other.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

inline void two_thread_for(std::size_t count, const std::function<void(std::size_t)>& body) {
  on_two_threads([&](int which) {
    for (auto i = static_cast<std::size_t>(which); i < count; i += 2) body(i);
  });
}

}  // namespace swum::test
