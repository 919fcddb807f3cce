// A classic CAN 2.0 frame (no CAN FD) and can-utils' cansend text form of it: the unit both
// ends of the CAN protocol exchange. Pure: no sockets (the bus adapters live in io/).
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace swum::protocol {

inline constexpr std::uint32_t kCanStandardIdMax = 0x7FF;
inline constexpr std::uint32_t kCanExtendedIdMax = 0x1FFFFFFF;

struct CanFrame {
  std::uint32_t id = 0;   // 11-bit (standard) or 29-bit (extended) identifier; for error
                          // frames the error class bits (linux/can/error.h CAN_ERR_*)
  bool extended = false;  // 29-bit identifier
  std::uint8_t dlc = 0;   // 0..8 payload bytes
  std::array<std::uint8_t, 8> data{};
  // Receive time, CLOCK_REALTIME since the epoch: the kernel's receive timestamp on a real
  // bus (SO_TIMESTAMPNS; zero if the kernel attached none, never made up), the delivery time
  // on the fake. Ignored by send().
  std::chrono::nanoseconds timestamp{0};
};

// Same identifier kind, identifier, length and the first dlc payload bytes (not the timestamp).
bool same_content(const CanFrame& a, const CanFrame& b);

// Empty when the frame can be sent; otherwise what is wrong with it.
std::string validate(const CanFrame& frame);

// can-utils' cansend notation: "123#DEADBEEF" (3 hex digits: standard), "1ABCDEF0#00" (8 hex
// digits: extended). parse_cansend returns what is wrong (empty when fine; `out` is changed
// only then).
std::string to_cansend(const CanFrame& frame);
// The same text into a caller's buffer, NUL-terminated, without allocating (a recording written
// on a per-frame path); returns its length. Any 32-bit identifier fits: 8 digits, '#', 16 digits.
inline constexpr std::size_t kCansendMaxLength = 8 + 1 + 16;
std::size_t to_cansend(const CanFrame& frame, std::span<char, kCansendMaxLength + 1> out);
std::string parse_cansend(std::string_view text, CanFrame& out);

}  // namespace swum::protocol
