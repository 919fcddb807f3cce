// What the SDO server and client write alike (CiA 301 7.2.4.3): the 8-byte frame, the abort
// transfer request (command specifier 4, the object's multiplexer, the abort code) and the
// little-endian 32-bit fields of bytes 4-7.
#pragma once

#include <cstddef>
#include <cstdint>

#include "can_frame.h"
#include "object_dictionary.h"

namespace swum::canopen {

inline void put_u32(protocol::CanFrame& frame, std::size_t at, std::uint32_t value) {
  for (std::size_t i = 0; i < 4; ++i) frame.data[at + i] = static_cast<std::uint8_t>(value >> (8 * i));
}

inline std::uint32_t u32_at(const protocol::CanFrame& frame, std::size_t at) {
  std::uint32_t value = 0;
  for (std::size_t i = 0; i < 4; ++i) value |= std::uint32_t{frame.data[at + i]} << (8 * i);
  return value;
}

// Every SDO frame has 8 bytes (CiA 301 7.2.4.3).
inline protocol::CanFrame sdo_frame(std::uint32_t id) {
  protocol::CanFrame frame;
  frame.id = id;
  frame.dlc = 8;
  return frame;
}

// CiA 301 7.2.4.3.17: abort SDO transfer.
inline protocol::CanFrame sdo_abort_frame(std::uint32_t id, std::uint16_t index, std::uint8_t sub, SdoAbort code) {
  protocol::CanFrame frame = sdo_frame(id);
  frame.data[0] = 0x80;
  frame.data[1] = static_cast<std::uint8_t>(index);
  frame.data[2] = static_cast<std::uint8_t>(index >> 8);
  frame.data[3] = sub;
  put_u32(frame, 4, static_cast<std::uint32_t>(code));
  return frame;
}

}  // namespace swum::canopen
