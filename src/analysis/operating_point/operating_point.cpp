#include "analysis/operating_point/operating_point.h"

#include <algorithm>
#include <cmath>

#include "analysis/steady_state/parabola_peak.h"
#include "formats/number_format.h"

namespace swum {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

PickResult undecided(PickResult r, std::string why) {
  r.decided = false;
  r.reason = std::move(why);
  return r;
}

}  // namespace

PickResult pick_operating_point(std::vector<CurveSample> samples, const PickOptions& options) {
  PickResult r;
  std::sort(samples.begin(), samples.end(),
            [](const CurveSample& a, const CurveSample& b) { return a.frequency_hz < b.frequency_hz; });
  // Merge duplicate frequencies (mean of the ok ones).
  std::vector<CurveSample> s;
  std::vector<int> counts;
  for (const CurveSample& x : samples) {
    if (!std::isfinite(x.frequency_hz)) continue;
    const bool ok = x.ok && std::isfinite(x.speed_mm_s);
    if (!s.empty() && std::abs(s.back().frequency_hz - x.frequency_hz) < 1e-6) {
      if (!ok) continue;
      if (!s.back().ok) {
        s.back() = x;
        counts.back() = 1;
        continue;
      }
      const int k = ++counts.back();
      s.back().speed_mm_s += (x.speed_mm_s - s.back().speed_mm_s) / k;
      s.back().spread_mm_s = std::max(s.back().spread_mm_s, x.spread_mm_s);
      continue;
    }
    CurveSample y = x;
    y.ok = ok;
    s.push_back(y);
    counts.push_back(1);
  }
  const int n = static_cast<int>(s.size());

  // Naive speed: linear interpolation between neighbouring ok points.
  for (int i = 0; i + 1 < n; ++i) {
    const double f0 = s[i].frequency_hz, f1 = s[i + 1].frequency_hz, f = options.naive_frequency_hz;
    if (s[i].ok && s[i + 1].ok && f >= f0 && f <= f1) {
      r.naive_speed_mm_s = s[i].speed_mm_s + (s[i + 1].speed_mm_s - s[i].speed_mm_s) * (f - f0) / (f1 - f0);
      break;
    }
  }
  for (int i = 0; i < n && !r.naive_speed_mm_s; ++i) {
    if (s[i].ok && std::abs(s[i].frequency_hz - options.naive_frequency_hz) < 1e-6)
      r.naive_speed_mm_s = s[i].speed_mm_s;
  }

  if (n < 4) return undecided(r, "too few points (" + std::to_string(n) + "; need at least 4)");
  std::vector<double> steps;
  for (int i = 0; i + 1 < n; ++i) steps.push_back(s[i + 1].frequency_hz - s[i].frequency_hz);
  r.grid_step_hz = median(steps);

  // Walk down from the top, as the resonance is approached, until the speed collapses.
  int peak = -1;
  int lowest = n - 1;  // lowest index of the walked branch
  for (int i = n - 1; i >= 0; --i) {
    const bool collapsed = !s[i].ok ||
                           (peak >= 0 && s[peak].speed_mm_s > 0.0 && s[i].speed_mm_s < 0.5 * s[peak].speed_mm_s);
    if (collapsed) {
      r.collapse_hz = s[i].frequency_hz;
      break;
    }
    lowest = i;
    if (peak < 0 || s[i].speed_mm_s > s[peak].speed_mm_s) peak = i;
  }
  if (peak < 0) return undecided(r, "no usable point at the top of the sweep");
  r.peak_frequency_hz = s[peak].frequency_hz;
  r.peak_speed_mm_s = s[peak].speed_mm_s;
  if (!(r.peak_speed_mm_s > 0.0)) return undecided(r, "no forward speed anywhere on the curve");
  if (peak == n - 1) {
    return undecided(r, format_numbers("speed is highest at the top of the sweep (%.0f Hz): sweep higher",
                                       r.peak_frequency_hz));
  }
  if (peak == 0) {
    return undecided(r, format_numbers("speed is highest at the bottom of the sweep (%.0f Hz) with no collapse: "
                                       "sweep lower",
                                       r.peak_frequency_hz));
  }

  // Noise: measured spread if any, and the scatter of second differences on the branch
  // (pure noise sigma gives E|d2| ~ 0.6745*sqrt(6) sigma at the median).
  std::vector<double> d2, spreads;
  for (int i = lowest + 1; i < n - 1; ++i) {
    d2.push_back(std::abs(s[i - 1].speed_mm_s - 2.0 * s[i].speed_mm_s + s[i + 1].speed_mm_s));
  }
  for (int i = lowest; i < n; ++i) {
    if (s[i].spread_mm_s >= 0.0) spreads.push_back(s[i].spread_mm_s);
  }
  r.noise_mm_s = std::max(1.4826 * median(d2) / std::sqrt(6.0), median(spreads));
  if (r.noise_mm_s > 0.1 * r.peak_speed_mm_s) {
    return undecided(r, format_numbers("too noisy: noise ~%.3g mm/s against a peak of %.3g mm/s", r.noise_mm_s,
                                       r.peak_speed_mm_s));
  }
  double min_above = r.peak_speed_mm_s;
  for (int i = peak + 1; i < n; ++i) min_above = std::min(min_above, s[i].speed_mm_s);
  const double prominence = r.peak_speed_mm_s - min_above;
  if (prominence < 6.0 * r.noise_mm_s || prominence < 0.05 * r.peak_speed_mm_s) {
    return undecided(r, format_numbers("no clear resonance peak: the speed falls only %.3g mm/s above the peak "
                                       "(noise ~%.3g mm/s)",
                                       prominence, r.noise_mm_s));
  }
  int upper_half = 0;
  for (int i = peak + 1; i < n; ++i) {
    if (s[i].speed_mm_s >= r.peak_speed_mm_s - 0.5 * prominence) ++upper_half;
  }
  if (upper_half < 2 || peak + 2 >= n) {
    return undecided(r, format_numbers("grid too coarse: fewer than 2 points on the upper half of the peak's high "
                                       "side (step %.0f Hz)",
                                       r.grid_step_hz));
  }

  // The peak finer than the grid: the vertex of the parabola through the best point and its
  // neighbours on the branch (parabola_peak_hz, as `swum calibrate --facts` locates a peak). When
  // the point below the best one has collapsed, the branch ends at the best point: it stays.
  r.peak_frequency_hz = peak > lowest
                            ? parabola_peak_hz(s[peak - 1].frequency_hz, s[peak - 1].speed_mm_s, s[peak].frequency_hz,
                                               s[peak].speed_mm_s, s[peak + 1].frequency_hz, s[peak + 1].speed_mm_s)
                            : s[peak].frequency_hz;

  // Margin on the high side: at least one grid step (the jump lies somewhere between the
  // peak and the next point below) and at least the distance over which the quadratic
  // flank above the peak drops by 2 x noise (the peak could be anywhere in there).
  const double f0 = s[peak].frequency_hz, f1 = s[peak + 1].frequency_hz, f2 = s[peak + 2].frequency_hz;
  const double y0 = s[peak].speed_mm_s, y1 = s[peak + 1].speed_mm_s, y2 = s[peak + 2].speed_mm_s;
  const double curvature = 2.0 * ((y2 - y1) / (f2 - f1) - (y1 - y0) / (f1 - f0)) / (f2 - f0);
  const double noise_width = curvature < 0.0 ? std::sqrt(4.0 * r.noise_mm_s / -curvature) : r.grid_step_hz;
  r.margin_hz = std::max({options.min_margin_hz, r.grid_step_hz, noise_width});
  // The operating frequency: peak + margin, up to the next whole hertz (an oscillator's setting;
  // the margin is never less than asked), its speed interpolated between the measured points
  // either side on the branch above the peak.
  r.frequency_hz = std::ceil(r.peak_frequency_hz + r.margin_hz - 1e-6);
  if (!(r.frequency_hz - r.peak_frequency_hz >= r.margin_hz - 0.5)) {  // frequencies far beyond any motor's
    return undecided(r, format_numbers("frequencies too large to resolve a margin of %.0f Hz", r.margin_hz));
  }
  int above = -1;
  for (int i = peak + 1; i < n; ++i) {
    if (!s[i].ok) break;
    if (s[i].frequency_hz >= r.frequency_hz) {
      above = i;
      break;
    }
  }
  if (above < 0) {
    return undecided(r, format_numbers("margin of %.0f Hz above the peak at %.0f Hz runs past the top of the sweep",
                                       r.margin_hz, r.peak_frequency_hz));
  }
  const CurveSample& a = s[above - 1];
  const CurveSample& b = s[above];
  r.speed_mm_s = a.speed_mm_s +
                 (b.speed_mm_s - a.speed_mm_s) * (r.frequency_hz - a.frequency_hz) / (b.frequency_hz - a.frequency_hz);
  r.decided = true;
  r.reason = format_numbers("peak %.4g mm/s at %.0f Hz; +%.0f Hz margin (grid step %.0f Hz", r.peak_speed_mm_s,
                            r.peak_frequency_hz, r.margin_hz, r.grid_step_hz);
  r.reason += format_numbers(", noise width %.0f Hz)", noise_width);
  r.reason += r.collapse_hz ? format_numbers("; collapses at %.0f Hz", *r.collapse_hz)
                            : std::string("; no collapse seen");
  return r;
}

}  // namespace swum
