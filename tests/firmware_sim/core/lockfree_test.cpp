#include "core/lockfree.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace swum::emu {
namespace {

TEST(BoundedQueue, FifoAndFull) {
  BoundedQueue<int, 4> q;
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(q.try_push(i));
  EXPECT_FALSE(q.try_push(4));
  int v = -1;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(q.try_pop(v));
    EXPECT_EQ(v, i);
  }
  EXPECT_FALSE(q.try_pop(v));
}

struct Item {
  int producer;
  int value;
};

TEST(BoundedQueue, ManyProducersLoseNothingAndKeepEachProducersOrder) {
  auto q = std::make_unique<BoundedQueue<Item, 256>>();
  constexpr int kProducers = 4, kItems = 50000;
  std::vector<std::thread> producers;
  for (int p = 0; p < kProducers; ++p)
    producers.emplace_back([&, p] {
      for (int i = 0; i < kItems; ++i)
        while (!q->try_push(Item{p, i})) std::this_thread::yield();
    });
  std::vector<int> next(kProducers, 0);
  int received = 0;
  Item item{};
  while (received < kProducers * kItems) {
    if (!q->try_pop(item)) continue;
    ASSERT_EQ(item.value, next[static_cast<std::size_t>(item.producer)]);
    ++next[static_cast<std::size_t>(item.producer)];
    ++received;
  }
  for (auto& t : producers) t.join();
}

struct Wide {
  std::uint64_t a, b, c, d;
};

TEST(Seqlock, ReadersNeverSeeATornValue) {
  Seqlock<Wide> lock;
  std::atomic<bool> done{false};
  std::atomic<bool> started{false};
  std::thread writer([&] {
    while (!started) std::this_thread::yield();
    for (std::uint64_t i = 1; i < 200000; ++i) lock.store(Wide{i, i, i, i});
    done = true;
  });
  std::uint64_t reads = 0;
  started = true;
  while (!done || reads == 0) {
    const Wide w = lock.load();
    ASSERT_TRUE(w.a == w.b && w.b == w.c && w.c == w.d);
    ++reads;
  }
  writer.join();
  EXPECT_EQ(lock.load().a, 199999U);
  EXPECT_GT(reads, 0U);
}

}  // namespace
}  // namespace swum::emu
