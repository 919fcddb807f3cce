#include "endpoint.h"

#include <limits>

#include "whole_number.h"

namespace swum::protocol {

std::string parse_modbus_endpoint(const std::string& text, ModbusEndpoint& out) {
  if (text.rfind("tcp://", 0) == 0) {
    const std::string rest = text.substr(6);
    const auto colon = rest.rfind(':');
    if (colon == std::string::npos) return "expected tcp://HOST:PORT";
    out.tcp = true;
    out.host = rest.substr(0, colon);
    const std::string port_text = rest.substr(colon + 1);
    const auto port = parse_whole_number(port_text, std::numeric_limits<long long>::min(),
                                         std::numeric_limits<long long>::max());
    if (!port) return "bad port in '" + text + "'";
    if (*port < 0 || *port > 65535) return "port " + port_text + " out of range (0 to 65535) in '" + text + "'";
    out.port = static_cast<std::uint16_t>(*port);
    if (out.host == "localhost") out.host = "127.0.0.1";
    return {};
  }
  if (text.rfind("rtu:", 0) == 0) {
    const std::string rest = text.substr(4);
    const auto colon = rest.rfind(':');
    out.tcp = false;
    if (colon == std::string::npos) {
      out.device = rest;
      return {};
    }
    out.device = rest.substr(0, colon);
    const auto baud = parse_whole_number(rest.substr(colon + 1), 1, std::numeric_limits<int>::max());
    if (!baud) return "bad baud rate in '" + text + "'";
    out.baud = static_cast<int>(*baud);
    return {};
  }
  return "expected tcp://HOST:PORT or rtu:/dev/DEVICE:BAUD, got '" + text + "'";
}

}  // namespace swum::protocol
