#include "core/lockstep_clock.h"

#include <chrono>

namespace swum::emu {

bool LockstepClock::advance(std::uint64_t ticks) {
  std::unique_lock lock(mutex_);
  if (closed_) return false;
  requested_ += ticks;
  const std::uint64_t target = requested_;
  requested_cv_.notify_one();
  completed_cv_.wait(lock, [&] { return completed_ >= target || closed_; });
  return completed_ >= target;
}

std::uint64_t LockstepClock::wait_for_request(std::uint64_t done, const std::atomic<bool>& stop) {
  std::unique_lock lock(mutex_);
  while (!closed_ && requested_ <= done) {
    if (stop.load(std::memory_order_relaxed)) return 0;
    requested_cv_.wait_for(lock, std::chrono::milliseconds(50));
  }
  return closed_ || stop.load(std::memory_order_relaxed) ? 0 : requested_;
}

void LockstepClock::completed(std::uint64_t done) {
  {
    std::lock_guard lock(mutex_);
    completed_ = done;
  }
  completed_cv_.notify_all();
}

void LockstepClock::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  completed_cv_.notify_all();
  requested_cv_.notify_all();
}

std::uint64_t LockstepClock::requested() const {
  std::lock_guard lock(mutex_);
  return requested_;
}

LockstepLoop::LockstepLoop(EmulatorCore& core, LockstepClock& clock, LockstepConfig config)
    : core_(core), clock_(clock), config_(config) {}

std::uint64_t LockstepLoop::run(const std::atomic<bool>& stop) {
  const auto start = std::chrono::steady_clock::now();  // for the exit report only
  std::uint64_t done = 0;
  for (;;) {
    std::uint64_t target = clock_.wait_for_request(done, stop);
    if (target == 0) break;
    if (config_.max_ticks != 0 && target > config_.max_ticks) target = config_.max_ticks;
    while (done < target && !stop.load(std::memory_order_relaxed)) {
      core_.tick();
      ++done;
    }
    clock_.completed(done);
    if (config_.max_ticks != 0 && done >= config_.max_ticks) break;
  }
  clock_.close();
  wall_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return done;
}

}  // namespace swum::emu
