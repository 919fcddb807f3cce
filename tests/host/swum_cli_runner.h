// Runs the real `swum` binary for the CLI contract tests, with stderr merged into stdout
// so one-line errors can be checked, and small scratch-file helpers.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace swum::test {

struct CliRun {
  int status = -1;     // exit status, -1 when the run did not finish within 120 s
  std::string output;  // stdout and stderr together
};

CliRun run_swum(const std::vector<std::string>& args);

// A file path in a per-suite folder under the system temporary directory.
// (In a directory of its own per running test, so tests run side by side never share a file.)
std::filesystem::path scratch_path(const std::string& suite, const std::string& name);

std::string read_file(const std::filesystem::path& path);

}  // namespace swum::test
