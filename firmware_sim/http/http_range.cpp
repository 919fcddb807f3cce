#include "http/http_range.h"

#include <charconv>
#include <optional>

namespace swum::emu {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// Decimal digits only, whole text (no sign, no space); nullopt otherwise or on overflow.
std::optional<std::uint64_t> digits(std::string_view s) {
  if (s.empty()) return std::nullopt;
  std::uint64_t value = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), value);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return std::nullopt;
  return value;
}

bool unit_is_bytes(std::string_view unit) {  // range units are case-insensitive
  constexpr std::string_view kBytes = "bytes";
  if (unit.size() != kBytes.size()) return false;
  for (std::size_t i = 0; i < unit.size(); ++i)
    if ((unit[i] | 0x20) != kBytes[i]) return false;
  return true;
}

}  // namespace

ByteRange resolve_byte_range(std::string_view header, std::uint64_t size) {
  const ByteRange whole;
  ByteRange unsatisfiable;
  unsatisfiable.kind = ByteRange::Kind::unsatisfiable;
  header = trim(header);
  if (header.empty()) return whole;
  const auto equals = header.find('=');
  if (equals == std::string_view::npos || !unit_is_bytes(trim(header.substr(0, equals)))) return whole;
  const std::string_view spec = trim(header.substr(equals + 1));
  if (spec.find(',') != std::string_view::npos) return whole;  // several ranges: the whole file
  const auto dash = spec.find('-');
  if (dash == std::string_view::npos) return unsatisfiable;
  const std::string_view first_text = trim(spec.substr(0, dash));
  const std::string_view last_text = trim(spec.substr(dash + 1));
  ByteRange r;
  r.kind = ByteRange::Kind::partial;
  if (first_text.empty()) {  // "-N": the last N bytes
    const auto n = digits(last_text);
    if (!n || *n == 0 || size == 0) return unsatisfiable;
    r.first = *n >= size ? 0 : size - *n;
    r.last = size - 1;
    return r;
  }
  const auto first = digits(first_text);
  if (!first || *first >= size) return unsatisfiable;
  r.first = *first;
  r.last = size - 1;
  if (!last_text.empty()) {  // "A-B": B past the end means to the end
    const auto last = digits(last_text);
    if (!last || *last < *first) return unsatisfiable;
    if (*last < r.last) r.last = *last;
  }
  return r;
}

}  // namespace swum::emu
