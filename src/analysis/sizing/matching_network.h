// PROVISIONAL (replaced by the network branch's file at merge): matching maths of docs/amplifier.md.
#pragma once

#include <complex>

namespace swum {

struct MatchingDesign {
  double angular_frequency_rad_s = 0.0;
  double voltage_v = 0.0;
  std::complex<double> admittance_siemens;
  double c0_parallel_inductance_h = 0.0;
  bool parallel_ok = false;
  double parallel_inductance_h = 0.0;
  double parallel_current_amplitude_a = 0.0;
  bool series_ok = false;
  double series_inductance_h = 0.0;
  double series_source_voltage_v = 0.0;
  double series_current_amplitude_a = 0.0;
};

[[nodiscard]] MatchingDesign design_matching(std::complex<double> admittance_siemens, double angular_frequency_rad_s,
                                             double voltage_v, double clamped_capacitance_f);
[[nodiscard]] std::complex<double> parallel_amplifier_current(std::complex<double> admittance_siemens,
                                                              double angular_frequency_rad_s, double voltage_v,
                                                              double parallel_inductance_h);
[[nodiscard]] std::complex<double> series_source_voltage(std::complex<double> admittance_siemens,
                                                         double angular_frequency_rad_s, double voltage_v,
                                                         double series_inductance_h);

}  // namespace swum
