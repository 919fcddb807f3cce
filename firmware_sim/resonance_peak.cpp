#include "resonance_peak.h"

#include <algorithm>
#include <cmath>

#include "model/effects.h"
#include "scenario_player.h"

namespace swum::emu {

ResonancePeak::ResonancePeak(const MotorModel& model) : model_(model), balance_(model) {}

ResonanceEstimate ResonancePeak::at(double vpp, double stator_temperature_c) {
  const long volts = std::lround(std::clamp(std::isfinite(vpp) ? vpp : 1.0, 1.0, 1.0e4));
  BackbonePoint point;
  {
    const std::lock_guard lock(mutex_);
    auto it = cache_.find(volts);
    if (it == cache_.end()) {
      if (cache_.size() > 2000) cache_.clear();  // bounded: every volt up to the amplifier's limit fits
      it = cache_.emplace(volts, balance_.backbone(static_cast<double>(volts))).first;
    }
    point = it->second;
  }
  const double rise_k = std::isfinite(stator_temperature_c) ? stator_temperature_c - kReferenceAmbientC : 0.0;
  const double stiffness = thermal_factors(model_.coefficients().effects, rise_k).stiffness;
  const double shift = stiffness > 0.0 ? std::sqrt(stiffness) : 1.0;
  return {static_cast<double>(volts), point.normal_peak_hz * shift, point.tangential_peak_hz * shift};
}

}  // namespace swum::emu
