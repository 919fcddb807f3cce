// Real SocketCAN adapter (PF_CAN / SOCK_RAW / CAN_RAW). Thin: every system call is checked and
// its errno reported; kernel filters (CAN_RAW_FILTER), kernel receive timestamps
// (SO_TIMESTAMPNS), kernel drop counter (SO_RXQ_OVFL), error frames (CAN_RAW_ERR_FILTER).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "can_bus.h"

namespace swum::io {

// Opening failed: no CAN support in the kernel, no such interface, not a CAN interface, ...
class CanOpenError : public std::runtime_error {
 public:
  CanOpenError(const std::string& what, int error_number) : std::runtime_error(what), error_number_(error_number) {}
  int error_number() const { return error_number_; }

 private:
  int error_number_;
};

class SocketCanBus final : public CanBus {
 public:
  struct Options {
    bool receive_error_frames = true;  // CAN_RAW_ERR_FILTER = CAN_ERR_MASK
    bool receive_own = false;          // CAN_RAW_RECV_OWN_MSGS
  };
  // Binds to `interface` (e.g. "vcan0"); throws CanOpenError with a clear message.
  explicit SocketCanBus(const std::string& interface) : SocketCanBus(interface, Options{}) {}
  SocketCanBus(const std::string& interface, Options options);
  ~SocketCanBus() override;
  SocketCanBus(const SocketCanBus&) = delete;
  SocketCanBus& operator=(const SocketCanBus&) = delete;

  CanResult send(const CanFrame& frame) override;
  CanResult receive(CanFrame& frame, std::chrono::milliseconds timeout) override;
  CanResult set_filters(std::span<const CanFilter> filters) override;
  std::string name() const override { return interface_; }

  int fd() const { return fd_; }
  // Frames the kernel dropped for this socket because its receive queue was full.
  std::uint32_t kernel_drops() const { return kernel_drops_; }

 private:
  std::string interface_;
  int fd_ = -1;
  std::uint32_t kernel_drops_ = 0;
};

}  // namespace swum::io
