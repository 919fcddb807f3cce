// What the tests of canopen/ share: a FrameSink that keeps what it is given, a frame's payload as
// a vector (for exact-byte assertions), a frame from bytes, and a master's write of a number into
// the dictionary (little-endian, of the given length), asserted to succeed.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <vector>

#include "frame_sink.h"
#include "object_dictionary.h"

namespace swum::canopen::test {

struct Frames final : FrameSink {
  std::vector<protocol::CanFrame> sent;
  void send(const protocol::CanFrame& frame) override { sent.push_back(frame); }
};

inline std::vector<std::uint8_t> bytes_of(const protocol::CanFrame& f) {
  return {f.data.begin(), f.data.begin() + f.dlc};
}

inline protocol::CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes, bool extended = false) {
  protocol::CanFrame f;
  f.id = id;
  f.extended = extended;
  f.dlc = static_cast<std::uint8_t>(bytes.size());
  std::size_t i = 0;
  for (const std::uint8_t b : bytes) f.data[i++] = b;
  return f;
}

// The abort of a master's write of `value` in `length` bytes.
inline SdoAbort try_write(ObjectDictionary& od, std::uint16_t index, std::uint8_t sub, std::uint32_t value,
                          std::size_t length) {
  const std::array<std::uint8_t, 4> bytes{static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8),
                                          static_cast<std::uint8_t>(value >> 16),
                                          static_cast<std::uint8_t>(value >> 24)};
  return od.write(od.slot(index, sub), std::span<const std::uint8_t>(bytes.data(), length));
}

inline void write(ObjectDictionary& od, std::uint16_t index, std::uint8_t sub, std::uint32_t value,
                  std::size_t length) {
  EXPECT_EQ(try_write(od, index, sub, value, length), SdoAbort::none)
      << std::hex << "0x" << index << " sub " << int(sub) << " = 0x" << value;
}

}  // namespace swum::canopen::test
