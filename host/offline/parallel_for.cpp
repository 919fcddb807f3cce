#include "offline/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace swum::host {

unsigned parallel_threads(unsigned jobs) { return jobs > 0 ? jobs : std::max(1u, std::thread::hardware_concurrency()); }

ParallelFor make_parallel_for(unsigned jobs) {
  const unsigned threads = parallel_threads(jobs);
  return [threads](std::size_t count, const std::function<void(std::size_t)>& body) {
    std::atomic<std::size_t> next{0};
    // An exception escaping a std::thread would terminate the process: the first one stops
    // the batch (no new tasks start) and is rethrown here once every worker has finished.
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto worker = [&] {
      for (std::size_t i = next++; i < count; i = next++) {
        try {
          body(i);
        } catch (...) {
          const std::lock_guard lock(failure_mutex);
          if (!failure) failure = std::current_exception();
          next = count;
        }
      }
    };
    std::vector<std::thread> pool;
    const std::size_t extra = std::min<std::size_t>(threads, count) - (count > 0 ? 1 : 0);
    for (std::size_t t = 0; t < extra; ++t) pool.emplace_back(worker);
    worker();
    for (auto& thread : pool) thread.join();
    if (failure) std::rethrow_exception(failure);
  };
}

}  // namespace swum::host
