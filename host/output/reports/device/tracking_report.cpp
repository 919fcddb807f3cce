#include "output/reports/device/tracking_report.h"

#include <nlohmann/json.hpp>

#include "formats/number_format.h"
#include "output/plot.h"

namespace swum::host {

std::string tracking_json(const std::vector<TrackRunSummary>& summaries) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const TrackRunSummary& s : summaries) {
    nlohmann::ordered_json blocks = nlohmann::ordered_json::array();
    for (const TrackBlock& b : s.blocks) {
      blocks.push_back({{"start_s", b.start_s},
                        {"end_s", b.end_s},
                        {"mean_speed_mm_s", b.mean_speed_mm_s},
                        {"best_speed_mm_s", b.best_speed_mm_s},
                        {"mean_rise_k", b.mean_rise_k},
                        {"margin_hz", b.margin_hz},
                        {"share", b.share}});
    }
    out.push_back({{"run", s.name},
                   {"min_share", s.min_share},
                   {"final_share", s.final_share},
                   {"final_frequency_hz", s.final_frequency_hz},
                   {"final_margin_hz", s.final_margin_hz},
                   {"final_rise_k", s.final_rise_k},
                   {"max_rise_k", s.max_rise_k},
                   {"blocks", blocks}});
  }
  return out.dump(2) + "\n";
}

std::string tracking_text(const std::vector<TrackRunSummary>& summaries) {
  std::string out = "run      min share  final share  final frequency (Hz)  final margin (Hz)  final rise (K)\n";
  for (const TrackRunSummary& s : summaries) {
    // "%-8s %9.3f  %11.3f  %20.1f  %17.1f  %14.1f\n", however long the run name or the numbers.
    out += s.name;
    if (s.name.size() < 8) out.append(8 - s.name.size(), ' ');
    out += format_numbers(" %9.3f  %11.3f  %20.1f  %17.1f", s.min_share, s.final_share, s.final_frequency_hz,
                          s.final_margin_hz);
    out += format_number(s.final_rise_k, "  %14.1f\n");
  }
  return out;
}

void write_tracking_plots(const std::filesystem::path& dir, const std::vector<TrackSeries>& runs,
                          const std::vector<TrackRunSummary>& summaries, const BestSpeedCurve& best, double amplitude_v,
                          double ambient_c) {
  PlotSpec share{"Share of the best speed at the same margin (" + format_number(amplitude_v) + " V)",
                 "device time (s)",
                 "mean speed / best at that temperature",
                 {}};
  PlotSpec frequency{
      "Drive frequency (" + format_number(amplitude_v) + " V)", "device time (s)", "frequency (kHz)", {}};
  PlotSpec speed{
      "Mover speed (dashed: best at the same margin, each run's temperature)", "device time (s)", "speed (mm/s)", {}};
  PlotSpec temperature{"Stator temperature", "device time (s)", "temperature (degC)", {}};
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const TrackSeries& r = runs[k];
    PlotSeries s{r.name, {}, {}, true, true};
    for (const TrackBlock& b : summaries[k].blocks) {
      s.x.push_back(0.5 * (b.start_s + b.end_s));
      s.y.push_back(b.share);
    }
    share.series.push_back(s);
    std::vector<double> khz, reference;
    for (std::size_t i = 0; i < r.time_s.size(); ++i) {
      khz.push_back(r.frequency_hz[i] * 1e-3);
      reference.push_back(best.speed_at(r.stator_temperature_c[i] - ambient_c));
    }
    frequency.series.push_back({r.name, r.time_s, khz, true, false});
    speed.series.push_back({r.name, r.time_s, r.speed_mm_s, true, false});
    speed.series.push_back({"best (" + r.name + ")", r.time_s, reference, true, false, true});
    temperature.series.push_back({r.name, r.time_s, r.stator_temperature_c, true, false});
  }
  if (!runs.empty()) {
    const double t0 = runs.front().time_s.front(), t1 = runs.front().time_s.back();
    share.series.push_back({"90 %", {t0, t1}, {0.9, 0.9}, true, false, true});
  }
  write_png_plot(share, dir / "tracking_share.png");
  write_png_plot(frequency, dir / "tracking_frequency.png");
  write_png_plot(speed, dir / "tracking_speed.png");
  write_png_plot(temperature, dir / "tracking_temperature.png");
}

}  // namespace swum::host
