#include "fake_can_bus.h"

#include <algorithm>
#include <cerrno>

namespace swum::io {
namespace {
std::chrono::nanoseconds realtime_now() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch());
}
}  // namespace

std::unique_ptr<FakeCanBus> FakeCanNetwork::attach(std::string name) {
  return std::unique_ptr<FakeCanBus>(new FakeCanBus(shared_from_this(), std::move(name)));
}

void FakeCanNetwork::drop_next(std::size_t count) {
  std::lock_guard lock(mutex_);
  drop_next_ = count;
}
void FakeCanNetwork::drop_if(std::function<bool(const CanFrame&)> predicate) {
  std::lock_guard lock(mutex_);
  drop_if_ = std::move(predicate);
}
void FakeCanNetwork::set_delay(std::chrono::nanoseconds delay) {
  std::lock_guard lock(mutex_);
  delay_ = delay < std::chrono::nanoseconds::zero() ? std::chrono::nanoseconds::zero() : delay;
}
void FakeCanNetwork::fail_next_sends(std::size_t count) {
  std::lock_guard lock(mutex_);
  fail_sends_ = count;
}
std::size_t FakeCanNetwork::delivered() const {
  std::lock_guard lock(mutex_);
  return delivered_;
}
std::size_t FakeCanNetwork::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

void FakeCanNetwork::enqueue(Endpoint& to, const CanFrame& frame, bool error) {
  Pending p{std::chrono::steady_clock::now() + delay_, frame, error};
  p.frame.timestamp = realtime_now() + delay_;
  // Keep the queue ordered by due time (a shorter delay set later may overtake).
  auto pos = std::upper_bound(to.queue.begin(), to.queue.end(), p.due,
                              [](auto due, const Pending& q) { return due < q.due; });
  to.queue.insert(pos, std::move(p));
  ++delivered_;
}

void FakeCanNetwork::inject_error_frame(std::uint32_t classes, std::array<std::uint8_t, 8> data) {
  {
    std::lock_guard lock(mutex_);
    CanFrame f;
    f.id = classes;
    f.dlc = 8;
    f.data = data;
    for (Endpoint* e : endpoints_) enqueue(*e, f, true);
  }
  arrived_.notify_all();
}

CanResult FakeCanNetwork::send_from(Endpoint* from, const CanFrame& frame) {
  if (auto why = validate(frame); !why.empty()) return CanResult{CanStatus::error, EINVAL, why};
  {
    std::lock_guard lock(mutex_);
    if (fail_sends_ > 0) {
      --fail_sends_;
      return CanResult{CanStatus::retry, ENOBUFS, "transmit queue of " + from->name + " full, retry later (injected)"};
    }
    if (drop_next_ > 0 || (drop_if_ && drop_if_(frame))) {
      if (drop_next_ > 0) --drop_next_;
      ++dropped_;
      return {};  // lost on the wire: the sender cannot tell
    }
    for (Endpoint* e : endpoints_) {
      if (e != from && matches_any(e->filters, frame)) enqueue(*e, frame, false);
    }
  }
  arrived_.notify_all();
  return {};
}

FakeCanBus::FakeCanBus(std::shared_ptr<FakeCanNetwork> network, std::string name) : network_(std::move(network)) {
  endpoint_.name = std::move(name);
  std::lock_guard lock(network_->mutex_);
  network_->endpoints_.push_back(&endpoint_);
}

FakeCanBus::~FakeCanBus() {
  std::lock_guard lock(network_->mutex_);
  auto& v = network_->endpoints_;
  v.erase(std::remove(v.begin(), v.end(), &endpoint_), v.end());
}

CanResult FakeCanBus::send(const CanFrame& frame) { return network_->send_from(&endpoint_, frame); }

CanResult FakeCanBus::receive(CanFrame& frame, std::chrono::milliseconds timeout) {
  using clock = std::chrono::steady_clock;
  const auto deadline = clock::now() + timeout;
  std::unique_lock lock(network_->mutex_);
  for (;;) {
    const auto now = clock::now();
    auto& q = endpoint_.queue;
    if (!q.empty() && q.front().due <= now) {
      FakeCanNetwork::Pending p = std::move(q.front());
      q.pop_front();
      frame = p.frame;
      if (p.error)
        return CanResult{CanStatus::error_frame, 0, decode_error_frame(frame).describe() + " on " + endpoint_.name};
      return {};
    }
    if (now >= deadline) {
      return CanResult{CanStatus::timeout, 0,
                       "no frame on " + endpoint_.name + " within " + std::to_string(timeout.count()) + " ms"};
    }
    const auto wake = q.empty() ? deadline : std::min(deadline, q.front().due);
    network_->arrived_.wait_until(lock, wake);
  }
}

CanResult FakeCanBus::set_filters(std::span<const CanFilter> filters) {
  for (const auto& f : filters) {
    if (auto why = validate(f); !why.empty()) return CanResult{CanStatus::error, EINVAL, why};
  }
  std::lock_guard lock(network_->mutex_);
  endpoint_.filters.assign(filters.begin(), filters.end());
  return {};
}

}  // namespace swum::io
