#include "analysis/sizing/matching_network.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace swum {
namespace {

void check_design_point(const MatchingDesignPoint& p) {
  if (!(p.angular_frequency_rad_s > 0.0) || !std::isfinite(p.angular_frequency_rad_s)) {
    throw std::invalid_argument("matching network: the angular frequency must be positive, not " +
                                std::to_string(p.angular_frequency_rad_s) + " rad/s");
  }
  if (!(p.amplitude_v > 0.0) || !std::isfinite(p.amplitude_v)) {
    throw std::invalid_argument("matching network: the target voltage amplitude must be positive, not " +
                                std::to_string(p.amplitude_v) + " V");
  }
  if (!std::isfinite(p.admittance_siemens.real()) || !std::isfinite(p.admittance_siemens.imag()) ||
      p.admittance_siemens == std::complex<double>{}) {
    throw std::invalid_argument("matching network: the admittance must be finite and non-zero");
  }
}

}  // namespace

std::complex<double> admittance_from_reading(double current_a, double phase_deg, double amplitude_v) {
  return std::polar(current_a / amplitude_v, phase_deg * std::numbers::pi / 180.0);
}

double c0_compensating_inductance_h(double w, double c0) {
  if (!(w > 0.0) || !(c0 > 0.0)) {
    throw std::invalid_argument("matching network: C0 compensation needs a positive frequency and C0");
  }
  return 1.0 / (w * w * c0);
}

ParallelMatching parallel_matching(const MatchingDesignPoint& p) {
  check_design_point(p);
  const double g = p.admittance_siemens.real(), b = p.admittance_siemens.imag();
  if (!(b > 0.0)) {
    throw std::invalid_argument("matching network: the phase's susceptance B = " + std::to_string(b) +
                                " S is not capacitive (B > 0): no parallel inductance cancels it");
  }
  // Y + 1/(j w L) = G + j (B - 1/(w L)) = G at L = 1/(w B).
  return {1.0 / (p.angular_frequency_rad_s * b), g * p.amplitude_v, 0.0};
}

SeriesMatching series_matching(const MatchingDesignPoint& p, double source_resistance_ohm) {
  check_design_point(p);
  const std::complex<double> z = 1.0 / p.admittance_siemens;
  const double r = z.real(), x = z.imag();
  if (!(x < 0.0)) {
    throw std::invalid_argument("matching network: the phase's reactance X = " + std::to_string(x) +
                                " ohm is not capacitive (X < 0): no series inductance cancels it");
  }
  // V_s = (R_s + j w L_s) I + V with I = V/Z: V_s = V (Z + R_s - j X)/Z = V (R + R_s)/Z at L_s = -X/w.
  const double magnitude = std::abs(z);
  return {-x / p.angular_frequency_rad_s, p.amplitude_v * (r + source_resistance_ohm) / magnitude,
          p.amplitude_v / magnitude, 0.0};
}

std::complex<double> parallel_amplifier_current(std::complex<double> y, double w, double v, double l) {
  return v * (y + 1.0 / std::complex<double>(0.0, w * l));
}

std::complex<double> series_source_voltage(std::complex<double> y, double w, double v, double l_s) {
  return v * (1.0 + std::complex<double>(0.0, w * l_s) * y);
}

}  // namespace swum
