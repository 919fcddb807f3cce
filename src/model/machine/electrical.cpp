#include "model/machine/electrical.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace swum {

ElectricalSums& ElectricalSums::operator+=(const ElectricalSums& o) {
  samples += o.samples;
  duration_s += o.duration_s;
  ss += o.ss;
  cc += o.cc;
  sc += o.sc;
  a_s += o.a_s;
  a_c += o.a_c;
  b_s += o.b_s;
  b_c += o.b_c;
  ma_s += o.ma_s;
  ma_c += o.ma_c;
  mb_s += o.mb_s;
  mb_c += o.mb_c;
  power_a += o.power_a;
  power_b += o.power_b;
  a_sq += o.a_sq;
  b_sq += o.b_sq;
  a_peak = std::max(a_peak, o.a_peak);
  b_peak = std::max(b_peak, o.b_peak);
  va_s += o.va_s;
  va_c += o.va_c;
  vb_s += o.vb_s;
  vb_c += o.vb_c;
  va_sq += o.va_sq;
  vb_sq += o.vb_sq;
  return *this;
}

ElectricalReadings electrical_readings(const ElectricalSums& sums, double phase_deg) {
  ElectricalReadings r;
  // Normal equations of I ~ x sin + y cos: [ss sc; sc cc] (x, y) = (sum I sin, sum I cos). Over a
  // quarter period or more the determinant is at least ~ (n/4)^2 / 10; below that the fit is
  // undetermined.
  const double det = sums.ss * sums.cc - sums.sc * sums.sc;
  if (!(sums.samples > 0.0) || !(det > 1e-3 * sums.samples * sums.samples)) return r;
  const double inv = 1.0 / det;
  const double rad_to_deg = 180.0 / std::numbers::pi;
  auto fit = [&](double is, double ic, double reference_deg, double& amplitude, double& phase) {
    const double x = inv * (sums.cc * is - sums.sc * ic);
    const double y = inv * (sums.ss * ic - sums.sc * is);
    amplitude = std::hypot(x, y);
    // x sin + y cos = |I| sin(theta + atan2(y, x)); the phase's voltage is at theta + reference.
    phase = amplitude > 0.0 ? wrap_phase_deg(std::atan2(y, x) * rad_to_deg - reference_deg) : 0.0;
  };
  fit(sums.a_s, sums.a_c, 0.0, r.current_a_a, r.phase_a_deg);
  fit(sums.b_s, sums.b_c, phase_deg, r.current_b_a, r.phase_b_deg);
  fit(sums.ma_s, sums.ma_c, 0.0, r.motional_current_a_a, r.motional_phase_a_deg);
  fit(sums.mb_s, sums.mb_c, phase_deg, r.motional_current_b_a, r.motional_phase_b_deg);
  r.power_a_w = sums.power_a / sums.samples;
  r.power_b_w = sums.power_b / sums.samples;
  double unused_phase_deg = 0.0;
  fit(sums.va_s, sums.va_c, 0.0, r.voltage_a_v, unused_phase_deg);
  fit(sums.vb_s, sums.vb_c, phase_deg, r.voltage_b_v, unused_phase_deg);
  r.rms_current_a_a = std::sqrt(sums.a_sq / sums.samples);
  r.rms_current_b_a = std::sqrt(sums.b_sq / sums.samples);
  r.peak_current_a_a = sums.a_peak;
  r.peak_current_b_a = sums.b_peak;
  r.apparent_power_a_va = std::sqrt(sums.va_sq / sums.samples) * r.rms_current_a_a;
  r.apparent_power_b_va = std::sqrt(sums.vb_sq / sums.samples) * r.rms_current_b_a;
  r.power_factor_a = r.apparent_power_a_va > 0.0 ? r.power_a_w / r.apparent_power_a_va : 0.0;
  r.power_factor_b = r.apparent_power_b_va > 0.0 ? r.power_b_w / r.apparent_power_b_va : 0.0;
  r.duration_s = sums.duration_s;
  r.valid = true;
  return r;
}

}  // namespace swum
