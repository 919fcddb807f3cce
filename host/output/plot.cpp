#include "output/plot.h"

#include <plstream.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace swum::host {
namespace {

// PLplot calls exit() on internal errors unless a handler returns; make it return so
// the caller gets an exception instead of a dead process.
int plplot_error_handler(const char* message) {
  (void)message;
  return 1;
}

struct Range {
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
  void include(double v) {
    if (!std::isfinite(v)) return;
    min = std::min(min, v);
    max = std::max(max, v);
  }
  bool valid() const { return min <= max; }
  void pad(double fraction) {
    double span = max - min;
    if (span <= 0.0) span = std::max(std::abs(max), 1.0);
    min -= fraction * span;
    max += fraction * span;
  }
};

// Distinguishable colours on white (PLplot colour map 0 indices 2..).
constexpr int kPalette[][3] = {{31, 119, 180}, {214, 39, 40},   {44, 160, 44},  {255, 127, 14},  {148, 103, 189},
                               {140, 86, 75},  {227, 119, 194}, {23, 190, 207}, {127, 127, 127}, {188, 189, 34}};
constexpr int kPaletteSize = static_cast<int>(sizeof(kPalette) / sizeof(kPalette[0]));

std::mutex plplot_mutex;  // PLplot keeps global state

}  // namespace

void write_png_plot(const PlotSpec& spec, const std::filesystem::path& path) {
  Range x_range;
  Range y_range;
  for (const auto& s : spec.series) {
    if (s.x.size() != s.y.size()) {
      throw std::runtime_error("plot " + path.string() + ": series '" + s.label + "' has different x and y lengths");
    }
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
        x_range.include(s.x[i]);
        y_range.include(s.y[i]);
      }
    }
  }
  if (!x_range.valid() || !y_range.valid()) {
    throw std::runtime_error("plot " + path.string() + ": no finite data to plot");
  }
  x_range.pad(0.03);
  y_range.pad(0.08);

  {  // Fail with errno before PLplot gets a chance to fail less clearly.
    std::ofstream probe(path, std::ios::binary | std::ios::trunc);
    if (!probe) {
      throw std::runtime_error("cannot write plot " + path.string() + ": " + std::strerror(errno));
    }
  }

  const std::lock_guard lock(plplot_mutex);
  plsexit(plplot_error_handler);
  auto pls = std::make_unique<plstream>();
  pls->sdev("pngcairo");
  pls->sfnam(path.c_str());
  pls->spage(0, 0, 1100, 750, 0, 0);
  pls->scol0(0, 255, 255, 255);  // background
  pls->scol0(1, 0, 0, 0);        // axes and text
  for (int i = 0; i < kPaletteSize; ++i) {
    pls->scol0(2 + i, kPalette[i][0], kPalette[i][1], kPalette[i][2]);
  }
  pls->init();
  pls->schr(0.0, 0.9);
  pls->col0(1);
  // The axes leave the right quarter of the page to the legend: a legend inside the axes hid
  // the curves under it (the speed-vs-frequency plot between 40.5 and 41 kHz).
  pls->adv(0);
  pls->vpor(0.09, 0.74, 0.11, 0.91);
  pls->wind(x_range.min, x_range.max, y_range.min, y_range.max);
  pls->box("bcgnst", 0.0, 0, "bcgnstv", 0.0, 0);  // frame, grid, ticks, numbers
  pls->lab(spec.x_label.c_str(), spec.y_label.c_str(), spec.title.c_str());

  const int n_series = static_cast<int>(spec.series.size());
  std::vector<PLINT> opt(n_series), text_colors(n_series, 1), line_colors(n_series), line_styles(n_series, 1),
      symbol_colors(n_series), symbol_numbers(n_series, 1);
  std::vector<PLFLT> line_widths(n_series, 2.0), symbol_scales(n_series, 1.0);
  std::vector<std::string> symbols(n_series, "#(728)");  // filled circle
  std::vector<const char*> texts(n_series), symbol_ptrs(n_series);

  for (int k = 0; k < n_series; ++k) {
    const PlotSeries& s = spec.series[k];
    const int color = 2 + k % kPaletteSize;
    std::vector<PLFLT> xs;
    std::vector<PLFLT> ys;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
        xs.push_back(s.x[i]);
        ys.push_back(s.y[i]);
      }
    }
    pls->col0(color);
    pls->width(2.0);
    pls->lsty(s.dashed ? 2 : 1);
    if (s.draw_line && xs.size() > 1) pls->line(static_cast<PLINT>(xs.size()), xs.data(), ys.data());
    pls->lsty(1);
    if (s.draw_markers && !xs.empty()) {
      pls->string(static_cast<PLINT>(xs.size()), xs.data(), ys.data(), "#(728)");
    }
    opt[k] = (s.draw_line ? PL_LEGEND_LINE : 0) | (s.draw_markers ? PL_LEGEND_SYMBOL : 0);
    line_colors[k] = color;
    line_styles[k] = s.dashed ? 2 : 1;
    symbol_colors[k] = color;
    texts[k] = s.label.c_str();
    symbol_ptrs[k] = symbols[k].c_str();
  }

  if (n_series > 0) {
    PLFLT legend_width = 0.0;
    PLFLT legend_height = 0.0;
    pls->col0(1);
    pls->width(1.0);
    pls->legend(&legend_width, &legend_height, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX,
                PL_POSITION_RIGHT | PL_POSITION_OUTSIDE, 0.02, 0.0, 0.1, 0, 0, 1, 0, 0, n_series, opt.data(), 1.0, 0.9,
                2.0, 1.0, text_colors.data(), texts.data(), nullptr, nullptr, nullptr, nullptr, line_colors.data(),
                line_styles.data(), line_widths.data(), symbol_colors.data(), symbol_scales.data(),
                symbol_numbers.data(), symbol_ptrs.data());
  }
  pls.reset();  // flushes and closes the PNG

  std::error_code ec;
  if (std::filesystem::file_size(path, ec) == 0 || ec) {
    throw std::runtime_error("plot " + path.string() + " was not written");
  }
}

}  // namespace swum::host
