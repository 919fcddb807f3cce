// The host's ParallelFor: every index once, and a task's exception reaches the caller
// instead of terminating the process from a worker thread.
#include "offline/parallel_for.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

namespace swum::host {
namespace {

TEST(ParallelFor, RunsEveryIndexOnce) {
  std::vector<std::atomic<int>> hits(1000);
  make_parallel_for(2)(hits.size(), [&](std::size_t i) { ++hits[i]; });
  for (const auto& h : hits) EXPECT_EQ(h.load(), 1);
  make_parallel_for(2)(0, [](std::size_t) { FAIL() << "no task for an empty batch"; });
}

TEST(ParallelFor, ATaskExceptionIsRethrownToTheCaller) {
  EXPECT_THROW(make_parallel_for(2)(10000,
                                    [&](std::size_t i) {
                                      if (i == 3) throw std::runtime_error("task 3");
                                    }),
               std::runtime_error);
}

// On one worker the stop is exact. With more, another worker may finish many trivial tasks
// while the exception unwinds (under ASan an unwind takes longer than 10000 of them), so
// only one worker pins down "no task starts after the failure".
TEST(ParallelFor, NoTaskStartsAfterAFailure) {
  std::atomic<int> ran{0};
  EXPECT_THROW(make_parallel_for(1)(10000,
                                    [&](std::size_t i) {
                                      ++ran;
                                      if (i == 3) throw std::runtime_error("task 3");
                                    }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 4);
}

}  // namespace
}  // namespace swum::host
