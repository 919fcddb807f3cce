// In-process CAN bus for unit tests, with the same contract as SocketCanBus: a frame sent by one
// endpoint reaches every *other* endpoint whose filters pass it (not the sender), in order,
// timestamped at delivery (CLOCK_REALTIME); send never blocks. Fault injection: drop frames,
// delay delivery, make sends report `retry` (ENOBUFS), inject error frames.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "can_bus.h"

namespace swum::io {

class FakeCanBus;

class FakeCanNetwork : public std::enable_shared_from_this<FakeCanNetwork> {
 public:
  static std::shared_ptr<FakeCanNetwork> create() { return std::shared_ptr<FakeCanNetwork>(new FakeCanNetwork); }
  std::unique_ptr<FakeCanBus> attach(std::string name = "fake0");

  // Faults, applied to frames sent after the call.
  void drop_next(std::size_t count);                             // lose the next `count` frames
  void drop_if(std::function<bool(const CanFrame&)> predicate);  // lose matching frames (nullptr: none)
  void set_delay(std::chrono::nanoseconds delay);                // delivery latency
  void fail_next_sends(std::size_t count);                       // next sends return retry (ENOBUFS)
  // Delivers an error frame (classes = CAN_ERR_* bits, data as in linux/can/error.h) to every endpoint.
  void inject_error_frame(std::uint32_t classes, std::array<std::uint8_t, 8> data = {});

  std::size_t delivered() const;  // frames handed to endpoints (counted per endpoint)
  std::size_t dropped() const;    // frames lost by drop_next / drop_if

 private:
  friend class FakeCanBus;
  struct Pending {
    std::chrono::steady_clock::time_point due;
    CanFrame frame;
    bool error = false;
  };
  struct Endpoint {
    std::string name;
    std::vector<CanFilter> filters;
    std::deque<Pending> queue;  // sorted by due time
  };
  FakeCanNetwork() = default;
  CanResult send_from(Endpoint* from, const CanFrame& frame);
  void enqueue(Endpoint& to, const CanFrame& frame, bool error);

  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::vector<Endpoint*> endpoints_;
  std::size_t drop_next_ = 0;
  std::function<bool(const CanFrame&)> drop_if_;
  std::chrono::nanoseconds delay_{0};
  std::size_t fail_sends_ = 0;
  std::size_t delivered_ = 0;
  std::size_t dropped_ = 0;
};

class FakeCanBus final : public CanBus {
 public:
  ~FakeCanBus() override;
  FakeCanBus(const FakeCanBus&) = delete;
  FakeCanBus& operator=(const FakeCanBus&) = delete;

  CanResult send(const CanFrame& frame) override;
  CanResult receive(CanFrame& frame, std::chrono::milliseconds timeout) override;
  CanResult set_filters(std::span<const CanFilter> filters) override;
  std::string name() const override { return endpoint_.name; }

 private:
  friend class FakeCanNetwork;
  FakeCanBus(std::shared_ptr<FakeCanNetwork> network, std::string name);
  std::shared_ptr<FakeCanNetwork> network_;
  FakeCanNetwork::Endpoint endpoint_;
};

}  // namespace swum::io
