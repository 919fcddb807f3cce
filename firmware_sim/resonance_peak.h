// Where the motor's resonances are at the present drive (the dashboard's operating point):
// the free stator's softening peaks of both modes at the drive amplitude, by harmonic balance
// (paper Fig. 9; docs/harmonic_balance.md), moved by the thermal effect's stiffness factor
// (docs/model.md "Effects": K -> K (1 + k_T dT), so a peak moves by sqrt(1 + k_T dT)). The
// mover's contact is not in it: under load the motional phase (telemetry) is the measured
// sign of which side of the resonance the drive is on. Called from the API's threads, never
// the loop's: a peak costs milliseconds and is cached per volt.
#pragma once

#include <map>
#include <mutex>

#include "analysis/harmonic_balance.h"
#include "http_json.h"
#include "model/motor_model.h"

namespace swum::emu {

class ResonancePeak {
 public:
  explicit ResonancePeak(const MotorModel& model);
  // At `vpp` (rounded to the volt; below 1 V: 1 V, the linear peak) and the stator temperature.
  ResonanceEstimate at(double vpp, double stator_temperature_c);

 private:
  const MotorModel& model_;
  FreeStatorHarmonicBalance balance_;
  std::mutex mutex_;
  std::map<long, BackbonePoint> cache_;  // by whole volts
};

}  // namespace swum::emu
