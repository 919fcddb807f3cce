// Shared by the tests: the calibrated motor's parameters (config/li2019.toml).
#pragma once

#include <fstream>
#include <sstream>

#include "formats/parameter_file.h"
#include "test_paths.h"

namespace swum::test {

inline MotorParameters calibrated_parameters() {
  std::ifstream in(swum::test::source_path("config/li2019.toml"));
  std::stringstream text;
  text << in.rdbuf();
  return parse_motor_parameters(text.str(), "li2019.toml");
}

}  // namespace swum::test
