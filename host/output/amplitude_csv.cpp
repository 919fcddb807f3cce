#include "output/amplitude_csv.h"

#include <array>
#include <cmath>
#include <optional>

#include "commands/command_error.h"
#include "formats/csv_cells.h"
#include "formats/csv_table.h"
#include "formats/number_format.h"

namespace swum::host {
namespace {

constexpr std::array<std::string_view, 4> kColumns = {"amplitude_v", "frequency_hz", "tip_normal_um",
                                                      "tip_tangential_um"};

[[noreturn]] void fail(std::string_view source, int line, int column, const std::string& what) {
  throw CommandError(csv_message(source, line, column, what));
}

std::string quoted_cell(std::string_view text) {
  std::string q = "'";
  q += printable_cell(text);
  q += "'";
  return q;
}

// Empty cell -> nullopt; otherwise a finite number or an error naming line and column.
std::optional<double> number_cell(std::string_view cell, std::string_view source, int line, int column,
                                  std::string_view name) {
  std::optional<double> value;
  if (const std::string problem = csv_number_problem(cell, name, value); !problem.empty()) {
    fail(source, line, column, problem);
  }
  return value;
}

}  // namespace

std::vector<AmplitudeMeasurement> parse_amplitude_csv(std::string_view text, std::string_view source,
                                                      int min_amplitudes) {
  const CsvTable table = read_csv_table(text);
  if (!table.header) fail(source, 1, 0, "no header line (the file is empty)");
  if (std::string retired = csv_retired_column_message(table, source); !retired.empty()) {
    throw CommandError(retired);
  }
  std::array<int, 4> index{-1, -1, -1, -1};  // cell index of each required column
  const std::vector<std::string_view>& header = table.header->cells;
  const int header_line = table.header->line;
  for (std::size_t c = 0; c < header.size(); ++c) {
    for (std::size_t k = 0; k < kColumns.size(); ++k) {
      if (header[c] == kColumns[k]) {
        if (index[k] >= 0) {
          fail(source, header_line, static_cast<int>(c) + 1, "column " + std::string(kColumns[k]) + " appears twice");
        }
        index[k] = static_cast<int>(c);
      }
    }
  }
  for (std::size_t k = 0; k < kColumns.size(); ++k) {
    if (index[k] < 0) {
      fail(source, header_line, static_cast<int>(header.size()) + 1,
           "missing column " + std::string(kColumns[k]) +
               " (the header must name amplitude_v,frequency_hz,tip_normal_um,tip_tangential_um)");
    }
  }
  std::vector<AmplitudeMeasurement> rows;
  int amplitudes = 0;
  for (const CsvRow& row : table.rows) {
    const int line_number = row.line;
    const std::vector<std::string_view>& cells = row.cells;
    int count_column = 0;
    if (const std::string problem = csv_cell_count_problem(table, row, count_column); !problem.empty()) {
      fail(source, line_number, count_column, problem);
    }
    std::array<std::optional<double>, 4> v;
    for (std::size_t k = 0; k < kColumns.size(); ++k) {
      const int column = index[k] + 1;
      v[k] = number_cell(cells[index[k]], source, line_number, column, kColumns[k]);
      if (k < 2 && !v[k]) {
        fail(source, line_number, column, "column " + std::string(kColumns[k]) + " is empty");
      }
      if (v[k] && *v[k] < 0.0) {
        fail(source, line_number, column,
             "column " + std::string(kColumns[k]) + ": negative value " + quoted_cell(cells[index[k]]) +
                 (k == 0 ? " (voltages are >= 0 V)" : ""));
      }
      if (k == 1 && *v[k] <= 0.0) {
        fail(source, line_number, column, "column frequency_hz: must be > 0");
      }
    }
    if (!v[2] && !v[3]) {
      fail(source, line_number, index[2] + 1,
           "both tip_normal_um and tip_tangential_um are empty (a row needs one amplitude)");
    }
    AmplitudeMeasurement m;
    m.amplitude_v = *v[0];
    m.frequency_hz = *v[1];
    m.tip_normal_um = v[2];
    m.tip_tangential_um = v[3];
    m.source_line = line_number;
    amplitudes += (v[2] ? 1 : 0) + (v[3] ? 1 : 0);
    rows.push_back(m);
  }
  if (amplitudes < min_amplitudes) {
    fail(source, table.last_content_line(), 0,
         "only " + std::to_string(amplitudes) + " amplitude values; fitting " + std::to_string(min_amplitudes) +
             " parameters needs at least " + std::to_string(min_amplitudes));
  }
  return rows;
}

std::string format_amplitude_csv(std::span<const AmplitudeMeasurement> data) {
  std::string out = "amplitude_v,frequency_hz,tip_normal_um,tip_tangential_um\n";
  for (const AmplitudeMeasurement& m : data) {
    out += format_number(m.amplitude_v, "%.10g") + "," + format_number(m.frequency_hz, "%.10g") + ",";
    if (m.tip_normal_um) out += format_number(*m.tip_normal_um, "%.10g");
    out += ",";
    if (m.tip_tangential_um) out += format_number(*m.tip_tangential_um, "%.10g");
    out += "\n";
  }
  return out;
}

}  // namespace swum::host
