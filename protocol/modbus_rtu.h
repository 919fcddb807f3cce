// Modbus RTU framing facts, both ends: how long a request is from its first bytes, and the
// CRC-16 that ends every frame (the Modbus over serial line specification). Pure: the
// emulator's RTU server frames a line with them to hold a per-frame deadline (libmodbus's own
// receive loop has none); the replies are still libmodbus's.
#pragma once

#include <cstdint>
#include <span>

namespace swum::protocol::modbus::rtu {

// The largest RTU ADU: unit id + 253-byte PDU + CRC (libmodbus's MODBUS_RTU_MAX_ADU_LENGTH).
inline constexpr int kMaxAduLength = 256;

// Total length of the RTU request whose first bytes are `frame`, as far as they tell (the rule
// libmodbus applies to requests: from the function code, then a byte count): more than
// frame.size() while bytes are missing, frame.size() when complete, -1 above kMaxAduLength bytes.
int request_length(std::span<const std::uint8_t> frame);
// CRC-16/MODBUS (polynomial 0xA001 reflected, initial 0xFFFF); sent low byte first.
std::uint16_t crc16(std::span<const std::uint8_t> bytes);

}  // namespace swum::protocol::modbus::rtu
