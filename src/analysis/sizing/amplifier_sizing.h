// Sizing an amplifier board (`swum size`, docs/sizing.md): at the drift-aware operating point of
// every row of an envelope (the rows of `swum band`: voltage x load x stator temperature rise), the
// electrical figures of each phase, the mechanical output, the efficiency and the heat into the
// stator; their worst cases over the envelope and the row each comes from; and the matching
// network sized at one design row (matching_network.h) with what the amplifier then delivers at
// every row of the envelope. Pure: band rows in, figures out.
#pragma once

#include <complex>
#include <cstddef>
#include <string>
#include <vector>

#include "analysis/operating_point/operating_band.h"
#include "analysis/sizing/matching_network.h"

namespace swum {

// One phase at one operating point (the drive-frequency components and the window's figures of
// ElectricalReadings, model/machine/electrical.h).
struct PhaseDuty {
  double voltage_v = 0.0;                   // amplitude of the phase voltage
  double current_rms_a = 0.0;               // true RMS of the terminal current
  double current_peak_a = 0.0;              // largest |I| of the window
  double current_amplitude_a = 0.0;         // drive-frequency component, zero-to-peak
  double phase_deg = 0.0;                   // current against voltage, + = the current leads
  double motional_phase_deg = 0.0;          // the motional current (C0's current taken out) against voltage
  double power_w = 0.0;                     // real power into the phase
  double apparent_power_va = 0.0;           // V_rms I_rms
  double power_factor = 0.0;                // power / apparent power
  std::complex<double> admittance_siemens;  // drive-frequency I / V (G + jB)
};

// What the amplifier delivers to one phase through the matching network sized at the design row.
struct MatchedDuty {
  // Parallel inductor across the phase, the amplifier driving the phase voltage directly.
  double parallel_current_amplitude_a = 0.0;
  double parallel_current_phase_deg = 0.0;  // against the phase voltage
  // Series inductor between the amplifier and the phase (no parallel one).
  double series_source_voltage_v = 0.0;  // amplitude the amplifier must put out for this row's voltage
  double series_current_amplitude_a = 0.0;
  double series_current_phase_deg = 0.0;  // against the amplifier's output voltage
};

struct SizingRow {
  double amplitude_v = 0.0;
  double load_n = 0.0;
  double temperature_rise_k = 0.0;
  PickResult pick;
  bool sized = false;  // decided, with the electrical port read at both grid points either side
  std::string reason;  // why not sized
  double frequency_hz = 0.0;
  double speed_mm_s = 0.0;
  PhaseDuty a, b;
  double electrical_power_w = 0.0;  // both phases
  double mechanical_power_w = 0.0;  // load x speed
  double efficiency = 0.0;          // mechanical / electrical
  double stator_heat_w = 0.0;       // modal damping power (what heats the stator: the thermal effect's P)
  MatchedDuty matched_a, matched_b;
};

// The largest (or, for the power factor, the smallest) value of a figure over the sized rows,
// the row it belongs to and the phase ('a', 'b'; ' ' for a figure of both).
struct Extreme {
  bool known = false;
  double value = 0.0;
  std::size_t row = 0;
  char phase = ' ';
};

struct SizingSummary {
  BandSummary band;  // the oscillator range (picked frequencies) and the peaks
  std::size_t sized = 0;
  Extreme current_rms_a, current_peak_a, apparent_power_va, power_w, power_factor_min, electrical_power_w,
      mechanical_power_w, efficiency_min, stator_heat_w;
  Extreme parallel_current_amplitude_a, parallel_phase_abs_deg, series_source_voltage_v, series_current_amplitude_a;
};

// The network sized at the design row for one phase (matching_network.h): both topologies,
// each with why it is missing when the phase admits none.
struct MatchingDesign {
  double angular_frequency_rad_s = 0.0;
  double voltage_v = 0.0;
  std::complex<double> admittance_siemens;
  double c0_parallel_inductance_h = 0.0;  // cancels C0 alone
  bool parallel_ok = false;
  std::string parallel_reason;
  double parallel_inductance_h = 0.0;  // cancels the whole susceptance at the design row
  double parallel_current_amplitude_a = 0.0;
  bool series_ok = false;
  std::string series_reason;
  double series_inductance_h = 0.0;
  double series_source_voltage_v = 0.0;
  double series_current_amplitude_a = 0.0;
};
[[nodiscard]] MatchingDesign design_matching(std::complex<double> admittance_siemens, double angular_frequency_rad_s,
                                             double voltage_v, double clamped_capacitance_f);

struct SizingResult {
  std::vector<SizingRow> rows;
  std::size_t design_row = 0;
  bool designed = false;  // false: the design row was not sized (no network; reason in the row)
  MatchingDesign design_a, design_b;
  SizingSummary summary;
};

// The design row: the highest voltage at the lowest load and lowest temperature rise of the grid,
// the corner that draws the most reactive current (the network is sized for the full drive of a
// cold, unloaded motor).
[[nodiscard]] std::size_t default_design_row(const std::vector<BandRow>& rows);

// Sizes from band rows computed with the electrical port (BandRow::points). clamped_capacitance_f:
// the stator's C0 (one phase).
[[nodiscard]] SizingResult size_amplifier(const std::vector<BandRow>& rows, double clamped_capacitance_f,
                                          std::size_t design_row);
// The same with a network designed before (another motor's, e.g. the nominal motor of a
// population): the figures of these rows, the amplifier's duty through that network.
[[nodiscard]] SizingResult size_amplifier_with_network(const std::vector<BandRow>& rows, const MatchingDesign& design_a,
                                                       const MatchingDesign& design_b);

// What an amplifier must deliver for a share `yield` of a motor population (swum size --spreads):
// each figure the smallest value that at least ceil(yield x motors) motors' worst cases over the
// envelope stay within (a motor with a row not sized, or a rejected draw, never counts as within);
// the oscillator the narrowest range holding every picked frequency of that many motors.
struct PopulationFigure {
  bool reached = false;
  double value = 0.0;
};
struct PopulationSizing {
  std::size_t motors = 0;
  std::size_t sized = 0;  // motors with every row sized
  double yield = 0.0;
  std::size_t needed = 0;  // ceil(yield x motors)
  bool oscillator_reached = false;
  double oscillator_low_hz = 0.0, oscillator_high_hz = 0.0;
  std::size_t oscillator_covered = 0;
  PopulationFigure current_rms_a, current_peak_a, apparent_power_va, power_w, stator_heat_w,
      parallel_current_amplitude_a, parallel_phase_abs_deg, series_source_voltage_v;
};
// motors[i]: motor i's sizing; nullptr = a rejected draw.
[[nodiscard]] PopulationSizing size_population(const std::vector<const SizingResult*>& motors, double yield);

// The figures of one row at its picked frequency, interpolated linearly between the curve's two
// grid points either side (both on the branch above the peak, as the pick's speed is). false with
// `reason` when the row is undecided or a neighbour failed.
[[nodiscard]] bool duty_at_pick(const BandRow& row, SizingRow& out);

}  // namespace swum
