#include "app/milliseconds.h"

#include <charconv>
#include <system_error>

namespace swum::emu {

std::string parse_milliseconds(std::string_view text, int min_ms, int max_ms, int& out) {
  const std::string range = " (" + std::to_string(min_ms) + " to " + std::to_string(max_ms) + " ms)";
  long long value = 0;
  const char* begin = text.data();
  const char* end = begin + text.size();
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (text.empty() || ec == std::errc::invalid_argument || ptr != end)
    return "'" + std::string(text) + "' is not a whole number of milliseconds" + range;
  if (ec == std::errc::result_out_of_range || value < min_ms || value > max_ms)
    return "'" + std::string(text) + "' is out of range" + range;
  out = static_cast<int>(value);
  return {};
}

}  // namespace swum::emu
