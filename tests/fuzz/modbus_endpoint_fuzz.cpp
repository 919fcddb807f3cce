// Fuzz target: where a Modbus device is, "tcp://HOST:PORT" or "rtu:/dev/DEVICE[:BAUD]", as both
// `swum-emu --modbus` and `swum --modbus` take it (protocol/endpoint.h parse_modbus_endpoint).
// Invariants: an accepted port or baud rate was written as a whole decimal number (issue 14:
// "tcp://127.0.0.1:15x" must not become port 15); the endpoint written back in its canonical
// form parses to the same endpoint; the baud rate is positive.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "endpoint.h"
#include "fuzz_check.h"

namespace {

using swum::protocol::ModbusEndpoint;

bool same(const ModbusEndpoint& a, const ModbusEndpoint& b) {
  return a.tcp == b.tcp && (a.tcp ? a.host == b.host && a.port == b.port : a.device == b.device && a.baud == b.baud);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(swum::fuzz::as_text(data, size));
  ModbusEndpoint endpoint;
  if (!swum::protocol::parse_modbus_endpoint(text, endpoint).empty()) return 0;
  const std::size_t colon = text.rfind(':');
  std::string canonical;
  if (endpoint.tcp) {
    FUZZ_CHECK(swum::fuzz::whole_decimal(std::string_view(text).substr(colon + 1)), "'%s' accepted as port %u",
               swum::fuzz::printable(text).c_str(), endpoint.port);
    canonical = "tcp://" + endpoint.host + ":" + std::to_string(endpoint.port);
  } else {
    FUZZ_CHECK(endpoint.baud > 0, "'%s' accepted with baud %d", swum::fuzz::printable(text).c_str(), endpoint.baud);
    const bool has_baud = colon > 3;  // a colon after "rtu:"
    if (has_baud) {
      FUZZ_CHECK(swum::fuzz::whole_decimal(std::string_view(text).substr(colon + 1)), "'%s' accepted as baud %d",
                 swum::fuzz::printable(text).c_str(), endpoint.baud);
    }
    canonical = "rtu:" + endpoint.device + ":" + std::to_string(endpoint.baud);
  }
  ModbusEndpoint again;
  const std::string error = swum::protocol::parse_modbus_endpoint(canonical, again);
  FUZZ_CHECK(error.empty() && same(again, endpoint), "'%s' accepted, its canonical form '%s' is not the same: %s",
             swum::fuzz::printable(text).c_str(), swum::fuzz::printable(canonical).c_str(), error.c_str());
  return 0;
}
