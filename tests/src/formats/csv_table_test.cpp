// The one CSV table reader (src/formats/csv_table.h): how a text is cut into header and rows in
// its two layouts, line numbers, and the shared wording of errors.
#include "formats/csv_table.h"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace swum {
namespace {

using Cells = std::vector<std::string_view>;

TEST(CsvTable, HandWrittenSkipsCommentsAndBlankLinesAnywhereAndTrims) {
  const std::string text =
      "# a comment\n\n  amplitude_v , frequency_hz\r\n  # indented comment\n \t\n100, 40000\r\n200,,\n";
  const CsvTable t = read_csv_table(text);
  ASSERT_TRUE(t.header);
  EXPECT_EQ(t.header->line, 3);
  EXPECT_EQ(t.header->cells, (Cells{"amplitude_v", "frequency_hz"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0].line, 6);
  EXPECT_EQ(t.rows[0].cells, (Cells{"100", "40000"}));
  EXPECT_EQ(t.rows[1].line, 7);
  EXPECT_EQ(t.rows[1].cells, (Cells{"200", "", ""}));
  EXPECT_EQ(t.last_line, 8);  // the final '\n' starts an empty line 8
  EXPECT_EQ(t.last_content_line(), 7);
  EXPECT_EQ(t.column("frequency_hz"), 1);
  EXPECT_EQ(t.column("load_n"), -1);
}

TEST(CsvTable, AsWrittenTakesLineOneAsTheHeaderAndKeepsEveryByte) {
  const CsvTable t = read_csv_table(" amplitude_v,status\r\n\n100, ok\r\n# not a comment\n", CsvLines::as_written);
  ASSERT_TRUE(t.header);
  EXPECT_EQ(t.header->line, 1);
  EXPECT_EQ(t.header->cells, (Cells{" amplitude_v", "status"}));
  EXPECT_EQ(t.column("amplitude_v"), -1);  // names are compared exactly
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0].line, 3);
  EXPECT_EQ(t.rows[0].cells, (Cells{"100", " ok"}));
  EXPECT_EQ(t.rows[1].line, 4);
  EXPECT_EQ(t.rows[1].cells, (Cells{"# not a comment"}));
  // An empty first line is the (empty) header; an empty text has none.
  const CsvTable blank_first = read_csv_table("\namplitude_v\n", CsvLines::as_written);
  ASSERT_TRUE(blank_first.header);
  EXPECT_EQ(blank_first.header->cells, (Cells{""}));
  EXPECT_FALSE(read_csv_table("", CsvLines::as_written).header);
}

TEST(CsvTable, NoContentMeansNoHeader) {
  for (const std::string_view text : {"", "\n", "# only a comment\n  \n"}) {
    const CsvTable t = read_csv_table(text);
    EXPECT_FALSE(t.header) << text;
    EXPECT_TRUE(t.rows.empty());
    EXPECT_EQ(t.last_content_line(), 0);
  }
  EXPECT_EQ(read_csv_table("").last_line, 1);
}

TEST(CsvTable, MessagesNameSourceLineAndColumn) {
  EXPECT_EQ(csv_message("data.csv", 3, 2, "column load_n is empty"), "data.csv:3:2: column load_n is empty");
  EXPECT_EQ(csv_message("data.csv", 1, 0, "no header line"), "data.csv:1: no header line");
  const CsvTable t = read_csv_table("a,b,c\n1,2\n1,2,3,4\n1,2,3\n");
  int column = 0;
  EXPECT_EQ(csv_cell_count_problem(t, t.rows[0], column), "expected 3 cells, found 2");
  EXPECT_EQ(column, 3);
  EXPECT_EQ(csv_cell_count_problem(t, t.rows[1], column), "expected 3 cells, found 4");
  EXPECT_EQ(column, 4);
  column = 0;
  EXPECT_EQ(csv_cell_count_problem(t, t.rows[2], column), "");
  EXPECT_EQ(column, 0);
}

TEST(CsvTable, NumberCellsAreEmptyFiniteOrAProblemNamingTheColumn) {
  std::optional<double> value = 1.0;
  EXPECT_EQ(csv_number_problem("", "amplitude_v", value), "");
  EXPECT_FALSE(value);
  EXPECT_EQ(csv_number_problem("+2.5e3", "amplitude_v", value), "");
  EXPECT_EQ(value, 2500.0);
  EXPECT_EQ(csv_number_problem("abc", "speed_mm_s", value), "column speed_mm_s: 'abc' is not a number");
  EXPECT_FALSE(value);
  EXPECT_EQ(csv_number_problem("inf", "speed_mm_s", value), "column speed_mm_s: 'inf' is not finite");
  EXPECT_EQ(csv_number_problem(std::string_view("4\0", 2), "f", value), "column f: '4\\x00' is not a number");
}

}  // namespace
}  // namespace swum
