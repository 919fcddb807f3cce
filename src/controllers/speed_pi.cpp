#include "controllers/speed_pi.h"

#include <algorithm>
#include <stdexcept>

namespace swum {

SpeedPi::SpeedPi(const SpeedPiGains& gains) : gains_(gains) {
  if (!(gains.kp_vpp_per_mm_s >= 0.0)) throw std::invalid_argument("--kp: must be >= 0");
  if (!(gains.ki_vpp_per_mm >= 0.0)) throw std::invalid_argument("--ki: must be >= 0");
  if (!(gains.max_vpp > 0.0)) throw std::invalid_argument("--max-vpp: must be > 0");
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
  const double proportional_vpp = gains_.kp_vpp_per_mm_s * error_mm_s;
  const double integrated_vpp = integral_vpp_ + gains_.ki_vpp_per_mm * error_mm_s * cycle_s;
  const double unclamped_vpp = proportional_vpp + integrated_vpp;
  const bool saturated_high = unclamped_vpp > gains_.max_vpp && error_mm_s > 0.0;
  const bool saturated_low = unclamped_vpp < 0.0 && error_mm_s < 0.0;
  // Saturated: integrate only as far as the output needs to reach the limit, never beyond it
  // (a frozen integral left the output short of the limit, e.g. 445 of 450 Vpp with one phase open).
  double next_vpp = integrated_vpp;
  if (saturated_high) next_vpp = std::max(integral_vpp_, gains_.max_vpp - proportional_vpp);
  if (saturated_low) next_vpp = std::min(integral_vpp_, -proportional_vpp);
  integral_vpp_ = std::clamp(next_vpp, 0.0, gains_.max_vpp);
  return std::clamp(proportional_vpp + integral_vpp_, 0.0, gains_.max_vpp);
}

}  // namespace swum
