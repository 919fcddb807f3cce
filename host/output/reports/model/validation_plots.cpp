#include "output/reports/model/validation_plots.h"

#include <string>
#include <utility>

#include "formats/number_format.h"
#include "output/plot.h"

namespace swum::host {
namespace {

PlotSeries series(std::string label, const XyCurve& curve) { return {std::move(label), curve.x, curve.y}; }

PlotSpec tip_trajectories(std::string title, const std::vector<TipOrbit>& orbits, bool label_by_voltage) {
  PlotSpec spec{std::move(title), "tangential tip displacement (um)", "normal tip displacement (um)", {}};
  for (const TipOrbit& o : orbits) {
    PlotSeries s = series(label_by_voltage ? format_number(o.paper_v, "%.0f") + " Vpp"
                                           : format_number(o.frequency_hz / 1000, "%.1f") + " kHz",
                          o.tip_um);
    s.draw_markers = false;
    spec.series.push_back(std::move(s));
  }
  return spec;
}

}  // namespace

void write_validation_plots(const ValidationCurves& curves, const std::filesystem::path& dir) {
  write_png_plot(
      {"No-load speed vs voltage at 40 kHz (paper Fig. 13)",
       "voltage on the paper's axis (Vpp)",
       "mover speed (mm/s)",
       {series("non-linear", curves.speed_vs_voltage_nonlinear), series("linear", curves.speed_vs_voltage_linear)}},
      dir / "fig13_speed_vs_voltage.png");

  // The linear curves first, lines only, then the non-linear ones with markers.
  PlotSpec by_frequency{
      "No-load speed vs frequency (paper Fig. 14)", "drive frequency (kHz)", "mover speed (mm/s)", {}};
  for (const FrequencyCurves& c : curves.speed_vs_frequency) {
    PlotSeries linear = series(format_number(c.paper_v, "%.0f") + " Vpp linear", c.linear);
    linear.draw_markers = false;
    by_frequency.series.push_back(std::move(linear));
  }
  for (const FrequencyCurves& c : curves.speed_vs_frequency) {
    by_frequency.series.push_back(series(format_number(c.paper_v, "%.0f") + " Vpp non-linear", c.nonlinear));
  }
  write_png_plot(by_frequency, dir / "fig14_speed_vs_frequency.png");

  // The paper's text gives the peak at 40.4, 40.2 and 39.6 kHz (model_spec §8 E10), as points.
  PlotSeries paper{"paper (Fig. 15 text)", {100, 250, 400}, {40.4, 40.2, 39.6}};
  paper.draw_line = false;
  write_png_plot({"Frequency of maximum no-load speed vs voltage (paper Fig. 15)",
                  "voltage on the paper's axis (Vpp)",
                  "frequency of max speed (kHz)",
                  {series("non-linear", curves.peak_vs_voltage_nonlinear),
                   series("linear", curves.peak_vs_voltage_linear), paper}},
                 dir / "fig15_peak_frequency_vs_voltage.png");

  PlotSpec by_load{
      "Speed vs load at drift-aware and naive frequency (paper Fig. 16)", "load force (N)", "mover speed (mm/s)", {}};
  for (const LoadCurve& c : curves.speed_vs_load) {
    by_load.series.push_back(
        series(format_number(c.paper_v, "%.0f") + " Vpp at " + format_number(c.frequency_hz / 1000, "%.2f") + " kHz",
               c.speed));
  }
  write_png_plot(by_load, dir / "fig16_speed_vs_load.png");

  write_png_plot(tip_trajectories("Free-stator tip trajectory at 39.5 kHz (paper Fig. 10)", curves.orbit_vs_voltage,
                                  true),
                 dir / "fig10_tip_trajectory_vs_voltage.png");
  write_png_plot(tip_trajectories("Free-stator tip trajectory at 400 Vpp (paper Fig. 11)", curves.orbit_vs_frequency,
                                  false),
                 dir / "fig11_tip_trajectory_vs_frequency.png");
}

}  // namespace swum::host
