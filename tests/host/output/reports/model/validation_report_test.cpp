#include "output/reports/model/validation_report.h"

#include <gtest/gtest.h>

namespace swum::host {
namespace {

TEST(ValidationFactsTable, OneRowPerFactWithItsVerdict) {
  FactResult held;
  held.id = "E8 dead zone";
  held.statement = "no motion below 50 V";
  held.paper_value = "50 V";
  held.model_value = "48 V";
  held.holds = true;
  FactResult failed = held;
  failed.id = "E9 peak";
  failed.model_value = "41.2 kHz";
  failed.holds = false;
  const std::string table = validation_facts_table({held, failed});
  EXPECT_EQ(table, "| fact | paper reports | paper value | model value | verdict |\n|---|---|---|---|---|\n"
                   "| E8 dead zone | no motion below 50 V | 50 V | 48 V | pass |\n"
                   "| E9 peak | no motion below 50 V | 50 V | 41.2 kHz | **fail** |\n");
  EXPECT_EQ(validation_facts_markdown("config/li2019.toml", table), "Config: `config/li2019.toml`\n\n" + table);
}

}  // namespace
}  // namespace swum::host
