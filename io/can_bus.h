// Narrow CAN interface of the device side (ros2_control-like: interface + thin real adapter +
// in-process fake obeying the same contract). Classic CAN 2.0 frames only (no CAN FD).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "can_frame.h"

namespace swum::io {

// The frame type and its text form live with the protocol (protocol/can_frame.h); the bus
// adapters carry them.
using protocol::CanFrame;
using protocol::kCanExtendedIdMax;
using protocol::kCanStandardIdMax;
using protocol::parse_cansend;
using protocol::same_content;
using protocol::to_cansend;
using protocol::validate;

// A receive filter: a frame passes when its identifier kind equals `extended` and
// (frame.id & mask) == (id & mask). Same semantics as the kernel's CAN_RAW_FILTER; remote frames
// (RTR) never pass a filter (SocketCanBus masks them out: no protocol here has any).
struct CanFilter {
  std::uint32_t id = 0;
  std::uint32_t mask = 0;
  bool extended = false;
};
bool matches(const CanFilter& filter, const CanFrame& frame);
// An empty filter list accepts every frame.
bool matches_any(std::span<const CanFilter> filters, const CanFrame& frame);
std::string validate(const CanFilter& filter);

enum class CanStatus {
  ok,           // frame sent / received
  timeout,      // nothing arrived within the timeout
  retry,        // send only: transmit queue full (ENOBUFS/EAGAIN); try again later
  error_frame,  // receive only: an error frame arrived (frame.id = error classes, see decode)
  error,        // anything else: errno + text in the result
};
const char* to_string(CanStatus status);

struct CanResult {
  CanStatus status = CanStatus::ok;
  int error_number = 0;  // errno, when the kernel reported one
  std::string message;   // human-readable detail for anything but ok
  bool ok() const { return status == CanStatus::ok; }
};

// Decoded error frame (classes from the id, details from the payload, linux/can/error.h).
struct CanErrorInfo {
  std::uint32_t classes = 0;
  bool bus_off = false;
  bool error_passive = false;  // controller or bus error-passive (data[1])
  bool error_warning = false;  // warning level reached (data[1])
  bool bus_error = false;      // protocol / bus error
  bool tx_timeout = false;
  bool lost_arbitration = false;
  bool no_ack = false;
  bool restarted = false;
  std::string describe() const;
};
CanErrorInfo decode_error_frame(const CanFrame& error_frame);

class CanBus {
 public:
  virtual ~CanBus() = default;
  // Never blocks: ok, retry (queue full) or error.
  virtual CanResult send(const CanFrame& frame) = 0;
  // Waits up to `timeout` for a frame passing the filters (or an error frame).
  virtual CanResult receive(CanFrame& frame, std::chrono::milliseconds timeout) = 0;
  // Replaces the receive filters; an empty list accepts every frame.
  virtual CanResult set_filters(std::span<const CanFilter> filters) = 0;
  virtual std::string name() const = 0;
};

}  // namespace swum::io
