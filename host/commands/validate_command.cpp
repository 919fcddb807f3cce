// `swum validate`: the paper's facts (model_spec §8) on a motor config and its linear
// variant, as a markdown table plus the paper-style plots (Figs. 10-11, 13-16). This is
// what produces docs/validation.md's evidence; the same criteria run as tests in
// tests/validation.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/studies/paper_facts.h"
#include "commands/commands.h"
#include "commands/config_option.h"
#include "offline/motor_config.h"
#include "offline/validation_curves.h"
#include "output/reports/model/validation_plots.h"
#include "output/reports/model/validation_report.h"
#include "output/text_files.h"

namespace swum::host {
namespace {

namespace fs = std::filesystem;

struct ValidateOptions {
  std::string config_path;
  std::string literal_path;
  std::string out_dir;
};

void run_validate(const ValidateOptions& o) {
  const MotorParameters parameters = load_motor_parameters(o.config_path);
  const MotorModel nonlinear(parameters);
  const MotorModel linear(linearised(parameters));
  const fs::path dir = o.out_dir;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create " + dir.string() + ": " + ec.message());

  PaperFacts facts(nonlinear, linear);
  std::vector<FactResult> results = facts.all();
  if (!o.literal_path.empty()) {
    const MotorModel literal(load_motor_parameters(o.literal_path));
    results.push_back(literal_reading_cross_check(literal));
  }
  const std::string table = validation_facts_table(results);
  write_text_file_atomically(dir / "facts.md", validation_facts_markdown(o.config_path, table));
  std::fputs(table.c_str(), stdout);

  // The figures: their curves run on the model (the peaks memoised by the facts), then drawn.
  write_validation_plots(validation_curves(parameters, nonlinear, linear, facts), dir);
}

}  // namespace

void add_validate_command(CLI::App& app) {
  auto o = std::make_shared<ValidateOptions>();
  CLI::App* sub = app.add_subcommand("validate", "Check the paper's facts and draw the paper-style plots");
  add_config_option(*sub, o->config_path, "motor parameter file (TOML)");
  sub->add_option("--literal", o->literal_path, "the paper-literal config, for the §9 cross-check");
  sub->add_option("--out", o->out_dir, "output folder (facts.md and PNG plots)")->required();
  sub->callback([o] { run_validate(*o); });
}

}  // namespace swum::host
