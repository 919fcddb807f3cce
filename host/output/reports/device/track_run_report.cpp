#include "output/reports/device/track_run_report.h"

#include <cmath>
#include <filesystem>

#include "formats/number_format.h"
#include "output/plot.h"

namespace swum::host {

void TrackPlotSeries::add(const TrackRow& r) {
  time_s.push_back(r.time_s);
  frequency_khz.push_back(r.frequency_hz * 1e-3);
  speed_mm_s.push_back(r.speed_mm_s);
  temperature_c.push_back(r.stator_temperature_c.value_or(std::nan("")));
  phase_deg.push_back(r.electrical ? r.electrical->motional_phase_a_deg : std::nan(""));
}

void write_track_plots(const TrackPlotSeries& s, const std::string& dir, const std::string& method) {
  std::filesystem::create_directories(dir);
  auto plot = [&](const std::string& file, const std::string& title, const std::string& y_label,
                  const std::vector<double>& y) {
    PlotSpec spec{title + " (swum track --method " + method + ")", "device time (s)", y_label, {}};
    spec.series.push_back({method, s.time_s, y, true, false});
    write_png_plot(spec, std::filesystem::path(dir) / file);
  };
  plot("track_frequency.png", "Drive frequency", "frequency (kHz)", s.frequency_khz);
  plot("track_speed.png", "Mover speed", "speed (mm/s)", s.speed_mm_s);
  bool any_temperature = false, any_phase = false;
  for (const double t : s.temperature_c) any_temperature |= std::isfinite(t);
  for (const double p : s.phase_deg) any_phase |= std::isfinite(p);
  if (any_temperature) plot("track_temperature.png", "Stator temperature", "temperature (degC)", s.temperature_c);
  if (any_phase) plot("track_phase.png", "Motional current phase, phase A", "phase (deg)", s.phase_deg);
}

std::string track_run_summary(const TrackRunResult& result, bool lockstep, const std::string& method,
                              const std::string& out_path) {
  return std::to_string(result.cycles) + " cycles (" + (lockstep ? "lockstep" : "wall time") + ", method " + method +
         ") -> " + out_path + "; final " + format_number(result.final_frequency_hz) + " Hz; peak " +
         (result.peak_hz ? format_number(*result.peak_hz) + " Hz" : "none") + "; phase set-point " +
         (result.phase_setpoint_deg ? format_number(*result.phase_setpoint_deg) + " deg" : "none") + "; " +
         std::to_string(result.collapses) + " collapses\n";
}

}  // namespace swum::host
