// `swum modes`: natural frequencies and modal constants of a motor parameter file.
#include <cstdio>
#include <memory>
#include <string>

#include "commands/commands.h"
#include "commands/config_option.h"
#include "model/motor_model.h"
#include "offline/motor_config.h"
#include "output/reports/model/modes_report.h"

namespace swum::host {
namespace {

struct ModesOptions {
  std::string config_path;
  bool json = false;
};

void run_modes(const ModesOptions& options) {
  const MotorModel model(load_motor_parameters(options.config_path));
  const ModalConstants& c = model.constants();
  std::fputs((options.json ? modes_json(c) : modes_text(c)).c_str(), stdout);
}

}  // namespace

void add_modes_command(CLI::App& app) {
  auto options = std::make_shared<ModesOptions>();
  CLI::App* sub = app.add_subcommand("modes", "Natural frequencies and modal constants of a motor");
  add_config_option(*sub, options->config_path, "motor parameter file (TOML)");
  sub->add_flag("--json", options->json, "print one JSON object");
  sub->callback([options] { run_modes(*options); });
}

}  // namespace swum::host
