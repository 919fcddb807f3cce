// Numbers as text: through printf patterns, the one formatter of the tables, labels and
// messages of src/ and host/ (every conversion in a pattern takes a double); and the shortest
// decimal that reads back as the same double, the one writer of swum-emu's trace files,
// settings, HTTP recordings and scenario texts (firmware_sim/core/trace.cpp,
// firmware_sim/app/emu_app.cpp, firmware_sim/http/http_recording.cpp, firmware_sim/core/scenario.cpp,
// which writes its exponents shorter).
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdio>
#include <string>

namespace swum {

namespace detail {
// The whole text however long: `Size` is only the stack buffer tried first (the usual
// case); a longer text (1e60 through %.6f) is printed again into a string of its length.
template <std::size_t Size, typename... Numbers>
[[nodiscard]] std::string printf_text(const char* pattern, Numbers... numbers) {
  char buffer[Size];
  const int length = std::snprintf(buffer, sizeof buffer, pattern, numbers...);
  if (length < 0) return {};
  if (static_cast<std::size_t>(length) < sizeof buffer) return std::string(buffer, static_cast<std::size_t>(length));
  std::string text(static_cast<std::size_t>(length), '\0');
  std::snprintf(text.data(), text.size() + 1, pattern, numbers...);
  return text;
}
}  // namespace detail

/// A line of a table or report through a printf `pattern` with any arguments (numbers, C
/// strings), never cut: for free text (a reason, a note) where a fixed buffer would lose the end
/// of the line and its newline.
template <typename... Arguments>
[[nodiscard]] std::string printf_string(const char* pattern, Arguments... arguments) {
  return detail::printf_text<256>(pattern, arguments...);
}

/// One number through a printf `format` (default %.6g: the shortest faithful text for tables
/// and labels), never cut.
[[nodiscard]] inline std::string format_number(double value, const char* format = "%.6g") {
  return detail::printf_text<64>(format, value);
}

/// A message with up to four numbers (`pattern` uses as many as it needs), never cut.
[[nodiscard]] inline std::string format_numbers(const char* pattern, double a, double b = 0.0, double c = 0.0,
                                                double d = 0.0) {
  return detail::printf_text<256>(pattern, a, b, c, d);
}

/// Appends the shortest decimal text that reads back (std::from_chars, strtod) as exactly
/// `value`: std::to_chars without a format ("0.1", "1e+21", "-0", "inf", "nan"); at most 24
/// characters.
inline void append_shortest_decimal(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

/// append_shortest_decimal as a string of its own.
[[nodiscard]] inline std::string shortest_decimal(double value) {
  std::string text;
  append_shortest_decimal(text, value);
  return text;
}

}  // namespace swum
