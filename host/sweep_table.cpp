#include "sweep_table.h"

#include <cstdio>
#include <map>
#include <set>
#include <utility>

#include "plot.h"

namespace swum::host {
namespace {

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

std::string label_for(double vpp, double load_n, bool several_loads) {
  std::string label = number(vpp) + " Vpp";
  if (several_loads) label += ", " + number(load_n) + " N";
  return label;
}

}  // namespace

std::string format_sweep_csv(const std::vector<SweepRow>& rows) {
  std::string csv = "vpp,frequency_hz,load_n,speed_mm_s,tip_normal_um,tip_tangential_um,status\n";
  for (const SweepRow& row : rows) {
    csv += number(row.vpp) + "," + number(row.frequency_hz) + "," + number(row.load_n) + ",";
    if (row.ok) {
      csv += number(row.speed_mm_s) + "," + number(row.tip_normal_um) + "," +
             number(row.tip_tangential_um);
    } else {
      csv += ",,";
    }
    csv += "," + row.status + "\n";
  }
  return csv;
}

void write_sweep_plot(const std::vector<SweepRow>& rows, const std::filesystem::path& path) {
  std::set<double> frequencies;
  std::set<double> loads;
  for (const SweepRow& row : rows) {
    frequencies.insert(row.frequency_hz);
    loads.insert(row.load_n);
  }
  const bool versus_frequency = frequencies.size() > 1;
  const bool several_loads = loads.size() > 1;

  // std::map keeps curves in (voltage, load) order for a stable legend.
  std::map<std::pair<double, double>, PlotSeries> curves;
  for (const SweepRow& row : rows) {
    const auto key = versus_frequency ? std::make_pair(row.vpp, row.load_n)
                                      : std::make_pair(0.0, row.load_n);
    PlotSeries& series = curves[key];
    if (series.label.empty()) {
      series.label = versus_frequency ? label_for(row.vpp, row.load_n, several_loads)
                                      : number(row.load_n) + " N load";
    }
    if (!row.ok) continue;
    series.x.push_back(versus_frequency ? row.frequency_hz / 1000.0 : row.vpp);
    series.y.push_back(row.speed_mm_s);
  }

  PlotSpec spec;
  if (versus_frequency) {
    spec.title = "Mover speed vs drive frequency";
    spec.x_label = "drive frequency (kHz)";
  } else {
    spec.title = "Mover speed vs drive voltage at " + number(*frequencies.begin() / 1000.0) + " kHz";
    spec.x_label = "drive voltage (Vpp)";
  }
  spec.y_label = "mover speed (mm/s)";
  for (auto& [key, series] : curves) spec.series.push_back(std::move(series));
  write_png_plot(spec, path);
}

}  // namespace swum::host
