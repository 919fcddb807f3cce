// Where the motor's resonances are at the present drive (the dashboard's operating point):
// the free stator's softening peaks of both modes at the drive amplitude and the stator
// temperature, by harmonic balance (paper Fig. 9; docs/harmonic_balance.md) with the thermal
// effect's factors on the modal stiffness and damping, as the simulator applies them (the
// softening depends on the damping too: a peak does not simply move by sqrt(stiffness)). The
// mover's contact is not in it: under load the motional phase (telemetry) is the measured sign
// of which side of the resonance the drive is on. Called from the API's threads, never the
// loop's: a peak costs milliseconds and is cached per volt and half kelvin.
#pragma once

#include <map>
#include <mutex>
#include <utility>

#include "analysis/free_stator/harmonic_balance.h"
#include "http/http_json.h"
#include "model/motor_model.h"

namespace swum::emu {

class ResonancePeak {
 public:
  explicit ResonancePeak(const MotorModel& model);
  // At `amplitude_v` (rounded to the volt; below 1 V: 1 V, the linear peak) and the stator temperature
  // (rounded to 0.5 K; without the thermal effect the temperature changes nothing).
  ResonanceEstimate at(double amplitude_v, double stator_temperature_c);

 private:
  const MotorModel& model_;
  std::mutex mutex_;
  std::map<std::pair<long, long>, BackbonePoint> cache_;  // by (whole volts, half kelvins of rise)
};

}  // namespace swum::emu
