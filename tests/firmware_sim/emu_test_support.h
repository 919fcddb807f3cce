// Shared by the firmware_sim unit tests: the li2019 motor model, built once.
#pragma once

#include <fstream>
#include <sstream>
#include <string>

#include "config/parameter_file.h"
#include "model/motor_model.h"

namespace swum::emu::test {

inline const MotorModel& li2019_model() {
  static const MotorModel model = [] {
    const std::string path = std::string(SWUM_SOURCE_DIR) + "/config/li2019.toml";
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return MotorModel(parse_motor_parameters(text.str(), path));
  }();
  return model;
}

}  // namespace swum::emu::test
