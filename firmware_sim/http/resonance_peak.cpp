#include "http/resonance_peak.h"

#include <algorithm>
#include <cmath>

#include "core/scenario_player.h"
#include "model/machine/effects.h"

namespace swum::emu {

ResonancePeak::ResonancePeak(const MotorModel& model) : model_(model) {}

ResonanceEstimate ResonancePeak::at(double amplitude_v, double stator_temperature_c) {
  const long volts = std::lround(std::clamp(std::isfinite(amplitude_v) ? amplitude_v : 1.0, 1.0, 1.0e4));
  const EffectCoefficients& effects = model_.coefficients().effects;
  const double rise_k = effects.thermal && std::isfinite(stator_temperature_c)
                            ? std::clamp(stator_temperature_c - kReferenceAmbientC, -200.0, 500.0)
                            : 0.0;
  const long half_kelvins = std::lround(rise_k * 2.0);
  const std::pair key{volts, half_kelvins};
  const std::lock_guard lock(mutex_);
  auto it = cache_.find(key);
  if (it == cache_.end()) {
    if (cache_.size() > 4000) cache_.clear();  // bounded; a run visits a few volts and kelvins at a time
    const ThermalFactors factors = thermal_factors(effects, static_cast<double>(half_kelvins) / 2.0);
    HarmonicBalanceOptions options;
    options.stiffness_factor = factors.stiffness;
    options.damping_factor = factors.damping;
    it = cache_.emplace(key, FreeStatorHarmonicBalance(model_, options).backbone(static_cast<double>(volts))).first;
  }
  return {static_cast<double>(volts), it->second.normal_peak_hz, it->second.tangential_peak_hz};
}

}  // namespace swum::emu
