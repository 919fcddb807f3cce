#include "commands/config_option.h"

#include "installation.h"

namespace swum::host {

void add_config_option(CLI::App& sub, std::string& path, const std::string& what) {
  sub.add_option("--config", path, what + "; default: li2019.toml of the data directory, the calibrated motor");
  // After this command's own options are parsed, before its callback runs: the default then
  // reaches the command exactly like a given path (and --help never looks for it).
  sub.parse_complete_callback([&path] {
    if (path.empty()) path = installation::default_config_path().string();
  });
}

}  // namespace swum::host
