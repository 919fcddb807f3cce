// A ParallelFor for the model tests (src/ starts no threads; the host has its own): tasks
// strided over two threads.
#pragma once

#include <thread>

#include "analysis/measured_point_model.h"

namespace swum::test {

inline void two_thread_for(std::size_t count, const std::function<void(std::size_t)>& body) {
  std::thread other([&] {
    for (std::size_t i = 1; i < count; i += 2) body(i);
  });
  for (std::size_t i = 0; i < count; i += 2) body(i);
  other.join();
}

}  // namespace swum::test
