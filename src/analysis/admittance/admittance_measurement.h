// A phase's admittance Y(f) = I/V as an impedance analyser measures it (docs/model.md,
// "Equivalent circuit"): one phase driven by a sinusoid of amplitude V, the other at 0 V (its
// ModelFaults gain 0: shorted), the drive-frequency component of the driven phase's terminal
// current (electrical.h) over the voltage, on a continuous down-sweep of the time-domain
// simulator (MotorSimulator), each point after a settle of several modal time constants 2M/C.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "model/parameters.h"

namespace swum {

enum class DrivenPhase { a, b };
// free: the stator alone, as on an analyser before assembly: no preload and no contact
// stiffness, so F_N = max(0, F_P - k_e q1) = 0 and no contact force acts (mounted_parameters).
// assembled: the motor as configured (preload on, the mover at rest on its guide).
enum class Mounting { free, assembled };

[[nodiscard]] std::string_view driven_phase_name(DrivenPhase phase);
[[nodiscard]] std::string_view mounting_name(Mounting mounting);

// The parameters of the measurement: the mounting applied, and the amplifier_droop effect off
// (an analyser imposes the terminal voltage; droop is the amplifier's source impedance).
[[nodiscard]] MotorParameters mounted_parameters(MotorParameters parameters, Mounting mounting);

struct AdmittanceSweepOptions {
  DrivenPhase phase = DrivenPhase::a;
  Mounting mounting = Mounting::free;
  double amplitude_v = 1.0;                   // terminal amplitude of the driven phase (V, zero-to-peak)
  std::vector<double> frequencies_hz;         // any order; measured from the highest down
  double first_settle_time_constants = 15.0;  // from rest at the first (highest) frequency
  double settle_time_constants = 10.0;        // after each frequency step of the down-sweep
  int window_periods = 40;                    // the current's fit window (whole drive periods)
};

struct AdmittancePoint {
  double frequency_hz = 0.0;
  double amplitude_v = 0.0;
  double current_a = 0.0;            // drive-frequency component, peak (A)
  double magnitude_siemens = 0.0;    // |Y| (S)
  double phase_deg = 0.0;            // arg Y (+90 = capacitive, current leads)
  double conductance_siemens = 0.0;  // G = Re Y
  double susceptance_siemens = 0.0;  // B = Im Y
  bool diverged = false;             // the simulator's runaway guard tripped at this point
};

// The longest modal time constant 2 M_i / C_i of the stator (s); infinite when a modal damping
// (stator.damping_l1_n_s_m, damping_b2_n_s_m) is 0.
[[nodiscard]] double longest_modal_time_constant_s(const MotorParameters& parameters);

// The most simulator steps one measure_admittance call takes (settles and windows of all points
// together): about 4-10 s of computing. A sweep that would need more (a very small modal damping
// makes the time constant, and so every settle, long) is refused before it starts.
inline constexpr double kMaxAdmittanceSweepSteps = 2e8;

// One row per frequency, in the order of options.frequencies_hz. Throws std::invalid_argument
// (one line naming the option or parameter) on an empty grid, a non-positive frequency, a
// negative or non-finite amplitude or settle factor, a modal damping of 0 (no finite time
// constant to settle for) or a sweep longer than kMaxAdmittanceSweepSteps, and ParameterError
// on bad parameters.
[[nodiscard]] std::vector<AdmittancePoint> measure_admittance(const MotorParameters& parameters,
                                                              const AdmittanceSweepOptions& options);

}  // namespace swum
