// How the analysis runs independent tasks: the caller's choice. src/ starts no threads; the host
// passes a thread pool (host/offline/parallel_for.h), tests and single runs the plain loop.
#pragma once

#include <cstddef>
#include <functional>

namespace swum {

// Runs body(0..count-1), possibly concurrently. What a body throws stops the batch and reaches
// the caller.
using ParallelFor = std::function<void(std::size_t count, const std::function<void(std::size_t)>& body)>;

// The plain loop.
inline void serial_for(std::size_t count, const std::function<void(std::size_t)>& body) {
  for (std::size_t i = 0; i < count; ++i) body(i);
}

}  // namespace swum
