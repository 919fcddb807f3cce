#include "output/reports/operating_point/pick_plots.h"

#include <cmath>
#include <map>

#include "formats/number_format.h"
#include "output/plot.h"

namespace swum::host {
namespace {
bool same(double a, double b) { return std::abs(a - b) < 1e-6 * std::max(1.0, std::abs(a)); }
}  // namespace

void write_speed_vs_frequency_plot(const std::vector<SweepRow>& sweep, const std::vector<VoltagePick>& picks,
                                   double load_n, const std::filesystem::path& path) {
  PlotSpec spec;
  spec.title = "Speed vs frequency, picked operating points (" + format_number(load_n) + " N load)";
  spec.x_label = "drive frequency (kHz)";
  spec.y_label = "mover speed (mm/s)";
  PlotSeries picked{"picked", {}, {}, false, true};
  for (const VoltagePick& p : picks) {
    PlotSeries curve{format_number(p.amplitude_v) + " V", {}, {}, true, true};
    for (const SweepRow& r : sweep) {
      if (r.ok && same(r.amplitude_v, p.amplitude_v) && same(r.load_n, load_n)) {
        curve.x.push_back(r.frequency_hz / 1000.0);
        curve.y.push_back(r.speed_mm_s);
      }
    }
    if (!curve.x.empty()) spec.series.push_back(std::move(curve));
    if (p.result.decided) {
      picked.x.push_back(p.result.frequency_hz / 1000.0);
      picked.y.push_back(p.result.speed_mm_s);
    }
  }
  if (!picked.x.empty()) spec.series.push_back(std::move(picked));
  write_png_plot(spec, path);
}

void write_frequency_vs_voltage_plot(const std::vector<VoltagePick>& picks, double naive_frequency_hz,
                                     const std::filesystem::path& path) {
  PlotSpec spec;
  spec.title = "Operating frequency vs drive voltage (resonance drift, cf. paper Fig. 15)";
  spec.x_label = "drive amplitude (V)";
  spec.y_label = "frequency (kHz)";
  PlotSeries picked{"picked (peak + margin)", {}, {}, true, true};
  PlotSeries peak{"speed peak", {}, {}, true, true};
  PlotSeries naive{"naive fixed " + format_number(naive_frequency_hz / 1000.0) + " kHz", {}, {}, true, false};
  for (const VoltagePick& p : picks) {
    naive.x.push_back(p.amplitude_v);
    naive.y.push_back(naive_frequency_hz / 1000.0);
    if (!p.result.decided) continue;
    picked.x.push_back(p.amplitude_v);
    picked.y.push_back(p.result.frequency_hz / 1000.0);
    peak.x.push_back(p.amplitude_v);
    peak.y.push_back(p.result.peak_frequency_hz / 1000.0);
  }
  spec.series = {std::move(picked), std::move(peak), std::move(naive)};
  write_png_plot(spec, path);
}

void write_speed_vs_load_plot(const std::vector<SweepRow>& load_rows, const std::vector<VoltagePick>& picks,
                              double naive_frequency_hz, const std::filesystem::path& path) {
  PlotSpec spec;
  spec.title = "Speed vs load: drift-aware vs naive frequency (cf. paper Fig. 16)";
  spec.x_label = "load force (N)";
  spec.y_label = "mover speed (mm/s)";
  for (const VoltagePick& p : picks) {
    if (!p.result.decided) continue;
    for (const auto& [frequency, label] : {std::pair{p.result.frequency_hz, std::string("picked ")},
                                           std::pair{naive_frequency_hz, std::string("naive ")}}) {
      PlotSeries s{format_number(p.amplitude_v) + " V, " + label + format_number(frequency / 1000.0) + " kHz",
                   {},
                   {},
                   true,
                   true};
      std::map<double, double> by_load;
      for (const SweepRow& r : load_rows) {
        if (r.ok && same(r.amplitude_v, p.amplitude_v) && same(r.frequency_hz, frequency))
          by_load[r.load_n] = r.speed_mm_s;
      }
      for (const auto& [load, speed] : by_load) {
        s.x.push_back(load);
        s.y.push_back(speed);
      }
      if (!s.x.empty()) spec.series.push_back(std::move(s));
    }
  }
  write_png_plot(spec, path);
}

}  // namespace swum::host
