// The calibrated motor and an admittance sweep of it, for the admittance tests.
#pragma once

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/admittance/admittance_measurement.h"
#include "formats/parameter_file.h"
#include "test_paths.h"

namespace swum::test {

inline MotorParameters calibrated_motor() {
  const std::string path = source_path("config/li2019.toml");
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return parse_motor_parameters(text.str(), path);
}

inline std::vector<double> frequency_grid(double start_hz, double stop_hz, double step_hz) {
  std::vector<double> f;
  for (double x = start_hz; x <= stop_hz + 1e-6; x += step_hz) f.push_back(x);
  return f;
}

inline std::vector<AdmittancePoint> sweep(const MotorParameters& p, DrivenPhase phase, Mounting mounting,
                                          double amplitude_v, const std::vector<double>& frequencies_hz) {
  AdmittanceSweepOptions o;
  o.phase = phase;
  o.mounting = mounting;
  o.amplitude_v = amplitude_v;
  o.frequencies_hz = frequencies_hz;
  return measure_admittance(p, o);
}

}  // namespace swum::test
