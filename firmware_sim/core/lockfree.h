// Lock-free exchange between the transport threads and the real-time loop:
//  - BoundedQueue: Vyukov's bounded MPMC ring (used as MPSC: transports push commands, the loop
//    pops them at the tick boundary). try_push never blocks and fails when full, so a command is
//    either accepted (and then applied, in order) or refused on the spot.
//  - Seqlock: single writer (the loop publishes telemetry once per tick), any number of readers
//    that retry while a write is in progress. Payload stored in atomic words: no data race.
// Neither allocates after construction.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace swum::emu {

template <class T, std::size_t Capacity>
class BoundedQueue {
  static_assert(Capacity >= 2 && (Capacity & (Capacity - 1)) == 0, "capacity must be a power of two");
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  BoundedQueue() {
    for (std::size_t i = 0; i < Capacity; ++i) cells_[i].sequence.store(i, std::memory_order_relaxed);
  }
  BoundedQueue(const BoundedQueue&) = delete;
  BoundedQueue& operator=(const BoundedQueue&) = delete;

  // Any thread. False when full.
  bool try_push(const T& value) {
    std::size_t pos = enqueue_.load(std::memory_order_relaxed);
    Cell* cell = nullptr;
    for (;;) {
      cell = &cells_[pos & kMask];
      const std::size_t seq = cell->sequence.load(std::memory_order_acquire);
      const auto diff = static_cast<std::intptr_t>(seq) - static_cast<std::intptr_t>(pos);
      if (diff == 0) {
        if (enqueue_.compare_exchange_weak(pos, pos + 1, std::memory_order_relaxed)) break;
      } else if (diff < 0) {
        return false;
      } else {
        pos = enqueue_.load(std::memory_order_relaxed);
      }
    }
    cell->value = value;
    cell->sequence.store(pos + 1, std::memory_order_release);
    return true;
  }

  // Any thread (the loop). False when empty.
  bool try_pop(T& value) {
    std::size_t pos = dequeue_.load(std::memory_order_relaxed);
    Cell* cell = nullptr;
    for (;;) {
      cell = &cells_[pos & kMask];
      const std::size_t seq = cell->sequence.load(std::memory_order_acquire);
      const auto diff = static_cast<std::intptr_t>(seq) - static_cast<std::intptr_t>(pos + 1);
      if (diff == 0) {
        if (dequeue_.compare_exchange_weak(pos, pos + 1, std::memory_order_relaxed)) break;
      } else if (diff < 0) {
        return false;
      } else {
        pos = dequeue_.load(std::memory_order_relaxed);
      }
    }
    value = cell->value;
    cell->sequence.store(pos + kMask + 1, std::memory_order_release);
    return true;
  }

  static constexpr std::size_t capacity() { return Capacity; }

 private:
  static constexpr std::size_t kMask = Capacity - 1;
  struct Cell {
    std::atomic<std::size_t> sequence{0};
    T value{};
  };
  std::array<Cell, Capacity> cells_;
  alignas(64) std::atomic<std::size_t> enqueue_{0};
  alignas(64) std::atomic<std::size_t> dequeue_{0};
};

template <class T>
class Seqlock {
  static_assert(std::is_trivially_copyable_v<T>);
  static constexpr std::size_t kWords = (sizeof(T) + 7) / 8;

 public:
  Seqlock() { store(T{}); }
  Seqlock(const Seqlock&) = delete;
  Seqlock& operator=(const Seqlock&) = delete;

  // One writer only.
  void store(const T& value) {
    std::array<std::uint64_t, kWords> buffer{};
    std::memcpy(buffer.data(), static_cast<const void*>(&value), sizeof(T));
    const std::uint64_t s = sequence_.load(std::memory_order_relaxed);
    sequence_.store(s + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    for (std::size_t i = 0; i < kWords; ++i) words_[i].store(buffer[i], std::memory_order_relaxed);
    sequence_.store(s + 2, std::memory_order_release);
  }

  // Any number of readers; returns a consistent copy.
  T load() const {
    std::array<std::uint64_t, kWords> buffer{};
    for (;;) {
      const std::uint64_t s1 = sequence_.load(std::memory_order_acquire);
      if (s1 & 1U) continue;
      for (std::size_t i = 0; i < kWords; ++i) buffer[i] = words_[i].load(std::memory_order_relaxed);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (sequence_.load(std::memory_order_relaxed) == s1) break;
    }
    T value;
    std::memcpy(static_cast<void*>(&value), buffer.data(), sizeof(T));
    return value;
  }

  // Number of completed stores (readers can wait for the next publication).
  std::uint64_t version() const { return sequence_.load(std::memory_order_acquire) / 2; }

 private:
  std::atomic<std::uint64_t> sequence_{0};
  std::array<std::atomic<std::uint64_t>, kWords> words_{};
};

}  // namespace swum::emu
