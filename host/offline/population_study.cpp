#include "offline/population_study.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "analysis/studies/population.h"
#include "model/motor_model.h"
#include "offline/model_pick.h"
#include "offline/offline_sweep.h"

namespace swum::host {

bool MotorOutcome::decided_everywhere() const {
  return !rejected && std::all_of(voltages.begin(), voltages.end(), [](const VoltageOutcome& v) { return v.decided; });
}

std::string MotorOutcome::status() const {
  if (rejected) return "rejected";
  return decided_everywhere() ? "ok" : "undecided";
}

MotorOutcome run_population_motor(const PopulationStudy& study, std::uint64_t motor) {
  MotorOutcome out;
  out.motor = motor;
  out.values = draw_spread_values(study.spreads, study.seed, motor);
  const MotorParameters parameters = with_drawn_values(study.nominal, study.spreads, out.values);
  const std::string name = "motor " + std::to_string(motor);
  try {
    validate_parameters(parameters, name);
  } catch (const ParameterError& e) {
    // Draws stay in each parameter's range (checked at load), so only a rule between
    // parameters can refuse a set; the motor is recorded as rejected, not redrawn.
    out.rejected = true;
    out.rejection = e.what();
    return out;
  }
  const MotorModel model(parameters);
  OfflineGrid grid{study.voltages, study.frequencies_hz, {study.load_n}};
  grid.jobs = 1;           // motors are the parallel unit
  grid.progress = false;   // one bar for the study (population_command), not one per motor
  grid.down_sweep = true;  // the operating point's curve, as swum pick --config takes it
  const std::vector<SweepRow> rows = sweep_model(model, grid);
  for (const VoltagePick& p : pick_voltages(rows, study.voltages, {study.load_n}, study.pick, name)) {
    VoltageOutcome v;
    v.amplitude_v = p.amplitude_v;
    v.decided = p.result.decided;
    v.frequency_hz = p.result.frequency_hz;
    v.speed_mm_s = p.result.speed_mm_s;
    v.peak_frequency_hz = p.result.peak_frequency_hz;
    v.reason = p.result.reason;
    out.voltages.push_back(v);
  }
  return out;
}

std::string encode_motor_outcome(const MotorOutcome& o) {
  nlohmann::json j;
  j["m"] = o.motor;
  j["x"] = o.values;
  j["r"] = o.rejected;
  j["w"] = o.rejection;
  nlohmann::json voltages = nlohmann::json::array();
  for (const VoltageOutcome& v : o.voltages) {
    voltages.push_back({v.amplitude_v, v.decided, v.frequency_hz, v.speed_mm_s, v.peak_frequency_hz, v.reason});
  }
  j["v"] = voltages;
  const std::vector<std::uint8_t> bytes = nlohmann::json::to_msgpack(j);
  return std::string(bytes.begin(), bytes.end());
}

MotorOutcome decode_motor_outcome(const std::string& bytes) {
  const nlohmann::json j = nlohmann::json::from_msgpack(bytes);
  MotorOutcome o;
  o.motor = j.at("m").get<std::uint64_t>();
  o.values = j.at("x").get<std::vector<double>>();
  o.rejected = j.at("r").get<bool>();
  o.rejection = j.at("w").get<std::string>();
  for (const auto& v : j.at("v")) {
    o.voltages.push_back({v.at(0).get<double>(), v.at(1).get<bool>(), v.at(2).get<double>(), v.at(3).get<double>(),
                          v.at(4).get<double>(), v.at(5).get<std::string>()});
  }
  return o;
}

}  // namespace swum::host
