// Shared by the firmware_sim unit tests: the li2019 motor model, built once, and its parameters.
#pragma once

#include <chrono>
#include <cstdint>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>

#include "core/scenario.h"
#include "formats/parameter_file.h"
#include "model/motor_model.h"
#include "test_paths.h"

namespace swum::emu::test {

// config/li2019.toml's parameters (to change some before building a model).
inline MotorParameters li2019_parameters() {
  const std::string path = swum::test::source_path("config/li2019.toml");
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return parse_motor_parameters(text.str(), path);
}

inline const MotorModel& li2019_model() {
  static const MotorModel model(li2019_parameters());
  return model;
}

// A scenario of --inject events, given in time order (as a parsed file keeps them).
// The same motor with the thermal effect on at the defaults of [effects.thermal].
inline const MotorModel& thermal_li2019_model() {
  static const MotorModel model = [] {
    MotorParameters p = li2019_parameters();
    p.effects.thermal.enabled = true;
    return MotorModel(p);
  }();
  return model;
}

inline Scenario scenario_of(std::initializer_list<std::string_view> injections, std::uint64_t seed = 0) {
  Scenario s;
  s.seed = seed;
  for (std::string_view text : injections) s.events.push_back(parse_injection(text));
  return s;
}

// Polls `condition` every millisecond until it holds (true) or `timeout` passes (false): for
// what the transports' threads do.
inline bool eventually(const std::function<bool()>& condition,
                       std::chrono::milliseconds timeout = std::chrono::milliseconds(10000)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

}  // namespace swum::emu::test
