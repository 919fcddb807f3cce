// Splitting one CSV line into cells, trimmed or as written (no quoting: the project's data
// files are numeric). The one CSV splitter of src/ and host/.
#pragma once

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace swum {

[[nodiscard]] inline std::string_view trim_cell(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r')) {
    text.remove_suffix(1);
  }
  return text;
}

// What split_csv_cells does with the blanks around a cell.
enum class CsvCellTrim {
  blanks,  // trim_cell every cell: hand-written data files (measurements, amplitudes)
  none,    // every byte kept: sweep tables as swum writes them (numbers are trimmed when parsed)
};

// The cells between commas: "a,,b," has four, an empty line one (empty) cell.
[[nodiscard]] inline std::vector<std::string_view> split_csv_cells(std::string_view line,
                                                                   CsvCellTrim trim = CsvCellTrim::blanks) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::string_view cell = line.substr(start, comma == std::string_view::npos ? comma : comma - start);
    cells.push_back(trim == CsvCellTrim::blanks ? trim_cell(cell) : cell);
    if (comma == std::string_view::npos) return cells;
    start = comma + 1;
  }
}

// A cell as it may appear in a one-line error: control bytes (a NUL would cut the message
// short) shown as \xNN.
[[nodiscard]] inline std::string printable_cell(std::string_view cell) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (const char ch : cell) {
    const auto byte = static_cast<unsigned char>(ch);
    if (byte < 0x20 || byte == 0x7f) {
      out += "\\x";
      out += kHex[byte >> 4];
      out += kHex[byte & 15];
    } else {
      out += ch;
    }
  }
  return out;
}

// A non-empty numeric cell (an optional leading '+'): nullptr and `value` set when it is a
// finite number, else what is wrong with it ("is not a number", "is not finite").
[[nodiscard]] inline const char* parse_number_cell(std::string_view cell, double& value) {
  const char* first = cell.data();
  const char* last = cell.data() + cell.size();
  if (first != last && *first == '+') ++first;
  const auto [end, error] = std::from_chars(first, last, value);
  if (cell.empty() || error != std::errc() || end != last) return "is not a number";
  if (!std::isfinite(value)) return "is not finite";
  return nullptr;
}

}  // namespace swum
