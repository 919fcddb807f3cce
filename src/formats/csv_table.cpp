#include "formats/csv_table.h"

#include <algorithm>

#include "formats/csv_cells.h"

namespace swum {

int CsvTable::column(std::string_view name) const {
  if (!header) return -1;
  const auto& cells = header->cells;
  const auto found = std::find(cells.begin(), cells.end(), name);
  return found == cells.end() ? -1 : static_cast<int>(found - cells.begin());
}

int CsvTable::last_content_line() const {
  if (!rows.empty()) return rows.back().line;
  return header ? header->line : 0;
}

CsvTable read_csv_table(std::string_view text, CsvLines lines) {
  const bool hand_written = lines == CsvLines::hand_written;
  const CsvCellTrim trim = hand_written ? CsvCellTrim::blanks : CsvCellTrim::none;
  CsvTable table;
  int number = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t newline = text.find('\n', start);
    std::string_view line = text.substr(start, newline == std::string_view::npos ? newline : newline - start);
    start = newline == std::string_view::npos ? text.size() + 1 : newline + 1;
    ++number;
    if (!hand_written && newline == std::string_view::npos && line.empty()) break;  // no line after the last '\n'
    if (hand_written) {
      line = trim_cell(line);
      if (line.empty() || line.front() == '#') continue;
    } else {
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (line.empty() && table.header) continue;
    }
    CsvRow row{number, split_csv_cells(line, trim)};
    if (table.header) {
      table.rows.push_back(std::move(row));
    } else {
      table.header = std::move(row);
    }
  }
  table.last_line = number;
  return table;
}

std::string csv_message(std::string_view source, int line, int column, std::string_view what) {
  std::string message(source);
  message += ":" + std::to_string(line);
  if (column > 0) message += ":" + std::to_string(column);
  message += ": ";
  message += what;
  return message;
}

std::string csv_retired_column_message(const CsvTable& table, std::string_view source) {
  const int vpp = table.column("vpp");
  if (vpp < 0) return {};
  return csv_message(source, table.header->line, vpp + 1,
                     "column 'vpp' is retired: name it amplitude_v (the terminal voltage amplitude per phase, V)");
}

std::string csv_cell_count_problem(const CsvTable& table, const CsvRow& row, int& column) {
  const std::size_t header_cells = table.header ? table.header->cells.size() : 0;
  if (row.cells.size() == header_cells) return {};
  column = static_cast<int>(std::min(row.cells.size(), header_cells)) + 1;
  return "expected " + std::to_string(header_cells) + " cells, found " + std::to_string(row.cells.size());
}

std::string csv_number_problem(std::string_view cell, std::string_view name, std::optional<double>& value) {
  value.reset();
  if (cell.empty()) return {};
  double number = 0.0;
  if (const char* problem = parse_number_cell(cell, number)) {
    return "column " + std::string(name) + ": '" + printable_cell(cell) + "' " + problem;
  }
  value = number;
  return {};
}

}  // namespace swum
