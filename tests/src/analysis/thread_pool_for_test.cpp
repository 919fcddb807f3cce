// The two-thread helpers of the model tests (thread_pool_for.h): every index once, and an
// exception on either thread fails the one test instead of terminating the test binary.
#include "thread_pool_for.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

namespace swum::test {
namespace {

TEST(TwoThreadFor, CallsTheBodyOnceForEveryIndexOnBothThreads) {
  std::vector<std::atomic<int>> calls(101);
  two_thread_for(calls.size(), [&](std::size_t i) { ++calls[i]; });
  for (std::size_t i = 0; i < calls.size(); ++i) EXPECT_EQ(calls[i].load(), 1) << "index " << i;
  two_thread_for(0, [](std::size_t) { FAIL() << "no index in an empty range"; });
}

TEST(OnTwoThreads, AnExceptionOnEitherThreadIsRethrownHereAfterBothFinished) {
  for (int thrower : {0, 1}) {
    std::atomic<int> finished{0};
    EXPECT_THROW(on_two_threads([&](int which) {
                   if (which == thrower) throw std::runtime_error("a worker's failure");
                   ++finished;
                 }),
                 std::runtime_error)
        << "thrown on thread " << thrower;
    EXPECT_EQ(finished.load(), 1) << "the other thread ran to its end";
  }
  EXPECT_THROW(on_two_threads([](int) { throw std::logic_error("both"); }), std::logic_error);
}

}  // namespace
}  // namespace swum::test
