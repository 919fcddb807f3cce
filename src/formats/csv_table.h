// The one CSV table reader of src/ and host/: a text cut into its header and rows, line numbers
// kept, comment and blank lines skipped, and the wording of "where" in one-line errors
// (SOURCE:LINE:COLUMN). Every reader of a table (measurements, amplitudes, sweep tables, swum
// track and band tables) keeps what its columns mean and which errors it raises; only these
// mechanics are shared. Cells are split by csv_cells.h (no quoting: the files are numeric).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace swum {

// How a text is cut into lines, header and cells.
enum class CsvLines {
  // Files people write or edit (measurements, amplitudes, swum track/band tables read back):
  // each line is trimmed of blanks and '\r' first; blank lines and lines starting with '#' are
  // skipped anywhere; the first other line is the header; cells are trimmed (CsvCellTrim::blanks).
  hand_written,
  // swum's own sweep tables read back: line 1 is the header (even when empty); a trailing '\r'
  // is dropped; empty lines after the header are skipped; no comments; cells are kept byte for
  // byte (CsvCellTrim::none: names and statuses are compared exactly).
  as_written,
};

struct CsvRow {
  int line = 0;  // 1-based line number in the text
  std::vector<std::string_view> cells;
};

// A text cut into a header and rows: views into the text, which must outlive the table. Cutting
// never fails; what the cells mean, and every error, is the reader's.
struct CsvTable {
  std::optional<CsvRow> header;  // absent when no line has content (as_written: an empty text)
  std::vector<CsvRow> rows;      // the lines after the header, in order
  int last_line = 0;             // the text's last line number (a final '\n' starts an empty line)

  /// The index of the first header cell named `name`; -1 when there is none.
  [[nodiscard]] int column(std::string_view name) const;
  /// The last line with content: the last row's, else the header's, else 0.
  [[nodiscard]] int last_content_line() const;
};

[[nodiscard]] CsvTable read_csv_table(std::string_view text, CsvLines lines = CsvLines::hand_written);

/// "SOURCE:LINE: WHAT", or "SOURCE:LINE:COLUMN: WHAT" when `column` (1-based) is > 0: the one
/// form of a table reader's errors.
[[nodiscard]] std::string csv_message(std::string_view source, int line, int column, std::string_view what);

/// The message for a header that names a retired column, with its source, line and column ("" when
/// none): "SOURCE:LINE:COLUMN: column 'vpp' is retired: name it amplitude_v (the terminal voltage
/// amplitude per phase, V)". Every table reader refuses such a file rather than read it with
/// another meaning (issue 34: what was "vpp" was the amplitude on the calibrated motor).
[[nodiscard]] std::string csv_retired_column_message(const CsvTable& table, std::string_view source);

/// A row whose cell count is not the header's: "" when it matches, else "expected N cells, found
/// M" with `column` set to the first cell that is missing or extra (1-based).
[[nodiscard]] std::string csv_cell_count_problem(const CsvTable& table, const CsvRow& row, int& column);

/// A number cell of the column `name`: "" with `value` nullopt when the cell is empty, "" with
/// `value` set when it is a finite number (an optional leading '+'), else "column NAME: 'CELL'
/// is not a number" / "... is not finite" (control bytes of CELL shown as \xNN).
[[nodiscard]] std::string csv_number_problem(std::string_view cell, std::string_view name,
                                             std::optional<double>& value);

}  // namespace swum
