// Where a Modbus device is: "tcp://HOST:PORT" or "rtu:/dev/DEVICE:BAUD", the form both the
// emulator (--modbus) and the host tool (--modbus) take. Pure text parsing.
#pragma once

#include <cstdint>
#include <string>

namespace swum::protocol {

// Parses "tcp://HOST:PORT" or "rtu:/dev/DEVICE:BAUD". Returns an error text, empty when fine.
struct ModbusEndpoint {
  bool tcp = true;
  std::string host = "127.0.0.1";
  std::uint16_t port = 1502;
  std::string device;
  int baud = 115200;
};
std::string parse_modbus_endpoint(const std::string& text, ModbusEndpoint& out);

}  // namespace swum::protocol
