#include "whole_number.h"

#include <charconv>

namespace swum::protocol {

std::optional<long long> parse_whole_number(std::string_view text, long long min, long long max) {
  long long value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc{} || ptr != end || value < min || value > max) return std::nullopt;
  return value;
}

}  // namespace swum::protocol
