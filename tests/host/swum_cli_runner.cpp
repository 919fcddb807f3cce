#include "swum_cli_runner.h"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <sstream>

#include "child_process.h"
#include "test_paths.h"

namespace swum::test {
namespace {

std::string shell_quote(const std::string& word) {
  std::string quoted = "'";
  for (char c : word) quoted += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace

CliRun run_swum(const std::vector<std::string>& args) {
  using namespace std::chrono_literals;
  std::string command = shell_quote(swum::test::swum_binary());
  for (const auto& a : args) command += " " + shell_quote(a);
  command += " 2>&1";
  ChildProcess child({"/bin/sh", "-c", command}, true);
  CliRun run;
  run.output = child.read_stdout(120s);
  run.status = child.wait(120s).value_or(-1);
  return run;
}

std::filesystem::path scratch_path(const std::string& suite, const std::string& name) {
  // One directory per test: ctest runs the tests of one file side by side, and two of them
  // writing one scratch file (synth renames its .partial into place) failed a run.
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  auto dir = std::filesystem::temp_directory_path() / suite;
  if (test != nullptr) dir /= std::string(test->test_suite_name()) + "." + test->name();
  std::filesystem::create_directories(dir);
  return dir / name;
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace swum::test
