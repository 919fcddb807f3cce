#include "output/reports/model/validation_report.h"

namespace swum::host {

std::string validation_facts_table(const std::vector<FactResult>& facts) {
  std::string table = "| fact | paper reports | paper value | model value | verdict |\n|---|---|---|---|---|\n";
  for (const FactResult& f : facts) {
    table += "| " + f.id + " | " + f.statement + " | " + f.paper_value + " | " + f.model_value + " | " +
             (f.holds ? "pass" : "**fail**") + " |\n";
  }
  return table;
}

std::string validation_facts_markdown(const std::string& config_path, const std::string& table) {
  return "Config: `" + config_path + "`\n\n" + table;
}

}  // namespace swum::host
