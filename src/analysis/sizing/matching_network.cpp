// PROVISIONAL (replaced by the network branch's file at merge).
#include "analysis/sizing/matching_network.h"

#include <cmath>

namespace swum {

MatchingDesign design_matching(std::complex<double> y, double w, double v, double c0) {
  MatchingDesign d;
  d.angular_frequency_rad_s = w;
  d.voltage_v = v;
  d.admittance_siemens = y;
  d.c0_parallel_inductance_h = 1.0 / (w * w * c0);
  if (y.imag() > 0.0) {
    d.parallel_ok = true;
    d.parallel_inductance_h = 1.0 / (w * y.imag());
    d.parallel_current_amplitude_a = y.real() * v;
  }
  const std::complex<double> z = 1.0 / y;
  if (z.imag() < 0.0) {
    d.series_ok = true;
    d.series_inductance_h = -z.imag() / w;
    d.series_source_voltage_v = v * z.real() / std::abs(z);
    d.series_current_amplitude_a = v / std::abs(z);
  }
  return d;
}

std::complex<double> parallel_amplifier_current(std::complex<double> y, double w, double v, double l) {
  return v * (y + 1.0 / std::complex<double>(0.0, w * l));
}

std::complex<double> series_source_voltage(std::complex<double> y, double w, double v, double l) {
  return v * (1.0 + std::complex<double>(0.0, w * l) * y);
}

}  // namespace swum
