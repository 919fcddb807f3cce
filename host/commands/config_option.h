// The --config option of the commands that need a motor: optional, defaulting to the calibrated
// motor of the data directory (li2019.toml; docs/install.md), in one place so every command says
// and does the same.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace swum::host {

// Adds --config to `sub` writing `path`; `what` is the help text's start (e.g. "motor parameter
// file (TOML)"). When --config is not given, `path` becomes the default motor's path once the
// command's options are parsed (an error naming where it looked if there is none).
void add_config_option(CLI::App& sub, std::string& path, const std::string& what);

}  // namespace swum::host
