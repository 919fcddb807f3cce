#include "model/machine/electrical.h"

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
  r.duration_s = sums.duration_s;
  r.valid = true;
  return r;
}

}  // namespace swum
