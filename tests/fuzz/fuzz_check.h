// Shared by the libFuzzer targets of tests/fuzz (docs/reliability.md, "Fuzzing"): a broken
// invariant aborts with what was expected, so libFuzzer keeps the input as a crash file.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

// Not assert(): the fuzz build is RelWithDebInfo (NDEBUG), and an invariant must hold there.
#define FUZZ_CHECK(condition, ...)                                                                  \
  do {                                                                                              \
    if (!(condition)) {                                                                             \
      std::fprintf(stderr, "fuzz invariant broken at %s:%d: %s\n", __FILE__, __LINE__, #condition); \
      std::fprintf(stderr, "fuzz invariant: " __VA_ARGS__);                                         \
      std::fputc('\n', stderr);                                                                     \
      std::abort();                                                                                 \
    }                                                                                               \
  } while (false)

namespace swum::fuzz {

// The input as text (parsers of files and command-line values take text).
inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// A whole decimal number as std::from_chars reads one into an int: an optional '-', then digits
// only (no sign '+', no spaces, no fraction or suffix).
inline bool whole_decimal(std::string_view text) {
  std::size_t i = (!text.empty() && text[0] == '-') ? 1 : 0;
  if (i == text.size()) return false;
  for (; i < text.size(); ++i) {
    if (text[i] < '0' || text[i] > '9') return false;
  }
  return true;
}

// Text for a message: control and non-ASCII bytes as \xNN (a NUL would cut it short).
inline std::string printable(std::string_view text) {
  std::string out;
  char hex[5];
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7F) {
      out += c;
    } else {
      std::snprintf(hex, sizeof hex, "\\x%02X", byte);
      out += hex;
    }
  }
  return out;
}

}  // namespace swum::fuzz
