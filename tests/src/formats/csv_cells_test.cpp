// The one CSV splitter (src/formats/csv_cells.h): trimmed cells for hand-written data files,
// cells as written for swum's own sweep tables.
#include "formats/csv_cells.h"

#include <gtest/gtest.h>

#include <string_view>
#include <vector>

namespace swum {
namespace {

using Cells = std::vector<std::string_view>;

TEST(CsvCells, BlanksAroundCellsAreTrimmedByDefault) {
  EXPECT_EQ(split_csv_cells(" amplitude_v ,\tfrequency_hz, 1 \r"), (Cells{"amplitude_v", "frequency_hz", "1"}));
}

TEST(CsvCells, NoneKeepsEveryByte) {
  EXPECT_EQ(split_csv_cells(" amplitude_v ,\tok, 1 \r", CsvCellTrim::none), (Cells{" amplitude_v ", "\tok", " 1 \r"}));
}

TEST(CsvCells, EmptyCellsCountInBothModes) {
  for (const CsvCellTrim trim : {CsvCellTrim::blanks, CsvCellTrim::none}) {
    EXPECT_EQ(split_csv_cells("a,,b,", trim), (Cells{"a", "", "b", ""}));
    EXPECT_EQ(split_csv_cells(",", trim), (Cells{"", ""}));
    EXPECT_EQ(split_csv_cells("", trim), (Cells{""}));
  }
}

}  // namespace
}  // namespace swum
