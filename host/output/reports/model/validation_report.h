// What `swum validate` prints and writes as text (model_spec §8): the paper's facts against the
// model as a markdown table (stdout and facts.md). Its figures: validation_plots.h.
#pragma once

#include <string>
#include <vector>

#include "analysis/studies/paper_facts.h"

namespace swum::host {

/// | fact | paper reports | paper value | model value | verdict |, one row per fact.
std::string validation_facts_table(const std::vector<FactResult>& facts);

/// facts.md: the config the facts were checked on, then the table.
std::string validation_facts_markdown(const std::string& config_path, const std::string& table);

}  // namespace swum::host
