// PNG line plots for people: axes with units, a title, a legend right of the axes. A thin layer over
// PLplot (pngcairo driver) so the rest of the host tool never sees plotting calls.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace swum::host {

struct PlotSeries {
  std::string label;
  std::vector<double> x;
  std::vector<double> y;
  bool draw_line = true;
  bool draw_markers = true;
  bool dashed = false;  // a reference curve
};

struct PlotSpec {
  std::string title;
  std::string x_label;  // with unit, e.g. "frequency (kHz)"
  std::string y_label;  // with unit, e.g. "speed (mm/s)"
  std::vector<PlotSeries> series;
};

/// Writes `spec` as a PNG. Throws std::runtime_error naming the path when the file
/// cannot be written or there is nothing finite to plot.
void write_png_plot(const PlotSpec& spec, const std::filesystem::path& path);

}  // namespace swum::host
