// Who the program is and where its installed data lives (docs/install.md): the one version of
// the project (CMake's project(VERSION)) and the data directory holding the motor configs, the
// scenarios and the protocol definitions (config/ of the checkout, share/swum-hil when installed).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace swum::installation {

// "0.1.0": the project's version, CMake's project(VERSION) (CHANGELOG.md lists them).
[[nodiscard]] std::string_view version();

// "PROGRAM 0.1.0 (git 0249405-dirty)": what --version prints; the git description of the checkout
// it was built from, when it was built from one.
[[nodiscard]] std::string version_line(std::string_view program);

// The data directory, first of: $SWUM_DATA_DIR (must hold li2019.toml, else an error naming it);
// DIR/../share/swum-hil next to the running executable (an installation, wherever its prefix);
// the checkout's config/ when the executable is a build of that checkout. Throws
// std::runtime_error, naming what was tried, when none holds li2019.toml.
[[nodiscard]] std::filesystem::path data_dir();

// The motor the tools use when --config is not given: li2019.toml of data_dir(), the calibrated
// motor (docs/validation.md).
[[nodiscard]] std::filesystem::path default_config_path();

// data_dir()'s search for an executable at `exe`, with `env` as $SWUM_DATA_DIR: the testable core
// (the executable's path and the environment as inputs). nullopt with `tried` filled when none.
[[nodiscard]] std::optional<std::filesystem::path> find_data_dir(const std::filesystem::path& exe, const char* env,
                                                                 std::string& tried);

}  // namespace swum::installation
