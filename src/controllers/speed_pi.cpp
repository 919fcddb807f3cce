#include "controllers/speed_pi.h"

#include <algorithm>
#include <stdexcept>

namespace swum {

SpeedPi::SpeedPi(const SpeedPiGains& gains) : gains_(gains) {
  if (!(gains.kp_v_per_mm_s >= 0.0)) throw std::invalid_argument("--kp: must be >= 0");
  if (!(gains.ki_v_per_mm >= 0.0)) throw std::invalid_argument("--ki: must be >= 0");
  if (!(gains.max_amplitude_v > 0.0)) throw std::invalid_argument("--max-amplitude-v: must be > 0");
}

double SpeedPi::update(double target_mm_s, double speed_mm_s, double cycle_s) {
  if (target_mm_s == 0.0) {
    reset();
    return 0.0;
  }
  // The amplitude sets the speed's magnitude; the phase (chosen by the caller) its direction.
  // Motion against the target's direction counts as a larger error.
  const double direction = target_mm_s > 0.0 ? 1.0 : -1.0;
  const double error_mm_s = direction * (target_mm_s - speed_mm_s);
  const double proportional_v = gains_.kp_v_per_mm_s * error_mm_s;
  const double integrated_v = integral_v_ + gains_.ki_v_per_mm * error_mm_s * cycle_s;
  const double unclamped_amplitude_v = proportional_v + integrated_v;
  const bool saturated_high = unclamped_amplitude_v > gains_.max_amplitude_v && error_mm_s > 0.0;
  const bool saturated_low = unclamped_amplitude_v < 0.0 && error_mm_s < 0.0;
  // Saturated: integrate only as far as the output needs to reach the limit, never beyond it
  // (a frozen integral left the output short of the limit, e.g. 445 of 450 V with one phase open).
  double next_amplitude_v = integrated_v;
  if (saturated_high) next_amplitude_v = std::max(integral_v_, gains_.max_amplitude_v - proportional_v);
  if (saturated_low) next_amplitude_v = std::min(integral_v_, -proportional_v);
  integral_v_ = std::clamp(next_amplitude_v, 0.0, gains_.max_amplitude_v);
  return std::clamp(proportional_v + integral_v_, 0.0, gains_.max_amplitude_v);
}

}  // namespace swum
