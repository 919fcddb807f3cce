// The amplitude PI of `swum control` (docs/host.md, "swum control"): the drive amplitude (V)
// is the actuator, the mover speed along the target's direction the measurement. Anti-windup
// by clamping the output and the integral to [0, max] and by conditional integration (the
// integral does not grow while the output is saturated in the direction the error pushes).
#pragma once

namespace swum {

// Defaults tuned on swum-emu with config/li2019.toml at 40 kHz (docs/host.md, "swum control").
inline constexpr double kDefaultKpVPerMmS = 0.5;
inline constexpr double kDefaultKiVPerMm = 50.0;

struct SpeedPiGains {
  double kp_v_per_mm_s = 0.0;      // V per mm/s of error
  double ki_v_per_mm = 0.0;        // V per (mm/s of error x s)
  double max_amplitude_v = 500.0;  // the output range is [0, max_amplitude_v]
};

class SpeedPi {
 public:
  explicit SpeedPi(const SpeedPiGains& gains);
  // One control cycle: the target speed (its sign is the direction), the measured speed (signed)
  // and the cycle's length -> the amplitude to drive. A zero target drives 0 V.
  double update(double target_mm_s, double speed_mm_s, double cycle_s);
  // The drive went off (fault, disable): restart from an empty integral.
  void reset() { integral_v_ = 0.0; }
  double integral_v() const { return integral_v_; }

 private:
  SpeedPiGains gains_;
  double integral_v_ = 0.0;
};

}  // namespace swum
