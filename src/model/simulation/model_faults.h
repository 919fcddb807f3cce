// Run-time motor/amplifier faults of the single-trajectory simulator (MotorSimulator::set_faults),
// set by the emulator's scenario timeline at tick boundaries, never inside a step. Each factor
// scales one term of the equations of motion (docs/model.md, "Run-time faults"); the defaults
// are the nominal motor.
#pragma once

#include <limits>
#include <string>

namespace swum {

struct ModelFaults {
  double phase_a_gain = 1.0;           // V_A amplitude factor: 0 = phase A shorted (V_A = 0), <1 = sag; [0, 2]
  double phase_b_gain = 1.0;           // V_B amplitude factor; [0, 2]
  double preload_factor = 1.0;         // F_P scale (preload loss), [0, 1]
  double guide_friction_factor = 1.0;  // guide friction scale (mu_s), [0, 10]
  bool jammed = false;                 // mover held at jam_position_m (hard stop): position fixed, velocity 0
  double jam_position_m = 0.0;         // NaN: where the mover is when the jam is set

  // No fault: every factor exactly 1 and not jammed (jam_position_m is then ignored).
  [[nodiscard]] bool nominal() const;
};

// Ranges of the factors (inclusive).
inline constexpr double kMaxPhaseGain = 2.0;
inline constexpr double kMaxGuideFrictionFactor = 10.0;

// One line naming the first bad field and its value ("phase_b_gain = -0.5 outside [0, 2]"),
// empty when every field is in range. NaN factors are bad; jam_position_m may be NaN, not
// infinite.
[[nodiscard]] std::string check(const ModelFaults& faults);

}  // namespace swum
