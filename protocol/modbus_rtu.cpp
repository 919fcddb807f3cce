#include "modbus_rtu.h"

namespace swum::protocol::modbus::rtu {

int request_length(std::span<const std::uint8_t> frame) {
  // Unit id, function code; then as libmodbus (_modbus_receive_msg, MSG_INDICATION): a fixed
  // part after the function code, a byte count for the multiple writes, the CRC.
  if (frame.size() < 2) return 2;
  const int function = frame[1];
  int fixed = 0;
  if (function <= 6) fixed = 4;                          // reads, single writes: address, count/value
  else if (function == 15 || function == 16) fixed = 5;  // + byte count
  else if (function == 22) fixed = 6;                    // mask write
  else if (function == 23) fixed = 9;                    // read/write multiple registers
  if (frame.size() < static_cast<std::size_t>(2 + fixed)) return 2 + fixed;
  int data = 0;
  if (function == 15 || function == 16) data = frame[6];
  else if (function == 23) data = frame[10];
  const int total = 2 + fixed + data + 2;
  return total > kMaxAduLength ? -1 : total;
}

std::uint16_t crc16(std::span<const std::uint8_t> bytes) {
  std::uint16_t crc = 0xFFFF;
  for (const std::uint8_t b : bytes) {
    crc ^= b;
    for (int i = 0; i < 8; ++i)
      crc = (crc & 1) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001) : static_cast<std::uint16_t>(crc >> 1);
  }
  return crc;
}

}  // namespace swum::protocol::modbus::rtu
