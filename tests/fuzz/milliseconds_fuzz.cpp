// Fuzz target: swum-emu's --modbus-*-ms values (firmware_sim/app/milliseconds.h
// parse_milliseconds).
// Input: bytes 0-3 and 4-7 = the allowed range's ends (little-endian int32, sorted), the rest
// the text.
// Invariants: an accepted text is a whole decimal number (an optional '-', then digits only)
// whose value is the result and lies in the range; a refused one leaves the result as it was
// and names the text in the message.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "app/milliseconds.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 8) return 0;
  std::int32_t a = 0;
  std::int32_t b = 0;
  std::memcpy(&a, data, 4);
  std::memcpy(&b, data + 4, 4);
  const int min_ms = std::min(a, b);
  const int max_ms = std::max(a, b);
  const std::string text(swum::fuzz::as_text(data + 8, size - 8));
  constexpr int kUntouched = -424242;
  int out = kUntouched;
  const std::string error = swum::emu::parse_milliseconds(text, min_ms, max_ms, out);
  if (!error.empty()) {
    FUZZ_CHECK(out == kUntouched, "refused '%s' but set %d", swum::fuzz::printable(text).c_str(), out);
    FUZZ_CHECK(error.rfind("'" + text + "'", 0) == 0, "message does not name the text: %s", error.c_str());
    return 0;
  }
  FUZZ_CHECK(swum::fuzz::whole_decimal(text), "'%s' accepted as %d", swum::fuzz::printable(text).c_str(), out);
  FUZZ_CHECK(std::stoll(text) == out, "'%s' read as %d", swum::fuzz::printable(text).c_str(), out);
  FUZZ_CHECK(out >= min_ms && out <= max_ms, "%d outside %d..%d", out, min_ms, max_ms);
  return 0;
}
