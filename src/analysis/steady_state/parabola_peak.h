// The frequency of a speed peak located finer than its grid, shared by the operating point
// (pick_operating_point: swum pick, band, population) and `swum calibrate --facts`' peak
// frequency. Header-only and free of the model: the fuzzed picking rule links it alone.
#pragma once

#include <algorithm>
#include <cmath>

namespace swum {

/// The vertex of the parabola through the best grid point (f0, y0) and its neighbours below
/// (fb, yb) and above (fa, ya), any spacing, kept within half a spacing of f0 (where the grid says
/// the peak is: y0 is the best of the three, so the vertex lies there unless noise bends the
/// parabola the wrong way). f0 itself when the three points do not bend down (a flat top, a
/// non-finite speed).
[[nodiscard]] inline double parabola_peak_hz(double fb, double yb, double f0, double y0, double fa, double ya) {
  const double below = f0 - fb, above = fa - f0;
  if (!(below > 0.0 && above > 0.0)) return f0;
  // Divided differences: the parabola's slopes at the two midpoints, then its second derivative.
  const double slope_below = (y0 - yb) / below, slope_above = (ya - y0) / above;
  const double curvature = 2.0 * (slope_above - slope_below) / (below + above);
  if (!std::isfinite(curvature) || !(curvature < 0.0)) return f0;
  // The parabola's slope at f0, from the two divided differences.
  const double slope_at_f0 = (slope_below * above + slope_above * below) / (below + above);
  return f0 + std::clamp(-slope_at_f0 / curvature, -0.5 * below, 0.5 * above);
}

}  // namespace swum
