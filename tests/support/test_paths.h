#pragma once
// Where the checkout and the built `swum` are, for tests and benchmarks that read the project's
// files or run its binary. The paths are written into one generated source (test_paths.cpp,
// tests/CMakeLists.txt) and not passed as -D flags: a flag holding an absolute path differs in
// every clone and would make each test unit miss the compiler cache (docs/testing.md, "Compiler
// cache"); this way one small unit is recompiled per clone.
#include <string>

namespace swum::test {

// The source tree's root, without a trailing slash (e.g. "/home/me/swum-hil").
const std::string& source_dir();
// source_dir() + "/" + relative, e.g. source_path("config/li2019.toml").
std::string source_path(const std::string& relative);
// The built `swum` executable.
const std::string& swum_binary();

}  // namespace swum::test
