#include "endpoint.h"

#include <charconv>
#include <stdexcept>

namespace swum::protocol {

std::string parse_modbus_endpoint(const std::string& text, ModbusEndpoint& out) {
  if (text.rfind("tcp://", 0) == 0) {
    const std::string rest = text.substr(6);
    const auto colon = rest.rfind(':');
    if (colon == std::string::npos) return "expected tcp://HOST:PORT";
    out.tcp = true;
    out.host = rest.substr(0, colon);
    try {
      const int port = std::stoi(rest.substr(colon + 1));
      if (port < 0 || port > 65535) return "port out of range";
      out.port = static_cast<std::uint16_t>(port);
    } catch (const std::exception&) {
      return "bad port in '" + text + "'";
    }
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
    try {
      out.baud = std::stoi(rest.substr(colon + 1));
    } catch (const std::exception&) {
      return "bad baud rate in '" + text + "'";
    }
    if (out.baud <= 0) return "bad baud rate in '" + text + "'";
    return {};
  }
  return "expected tcp://HOST:PORT or rtu:/dev/DEVICE:BAUD, got '" + text + "'";
}

}  // namespace swum::protocol
