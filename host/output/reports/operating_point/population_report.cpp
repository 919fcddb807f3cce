#include "output/reports/operating_point/population_report.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <optional>
#include <utility>

#include "analysis/studies/population.h"
#include "formats/number_format.h"

namespace swum::host {
namespace {

using Json = nlohmann::ordered_json;

std::string voltage_label(double amplitude_v) { return format_number(amplitude_v) + "v"; }  // "400v": 400 V amplitude

std::string csv_safe(std::string text) {
  std::replace(text.begin(), text.end(), ',', ';');
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}

// A motor's operating frequencies over the voltages, as [lowest, highest]; none when it has
// no operating frequency at some voltage (rejected, undecided).
std::optional<std::pair<double, double>> span_of(const MotorOutcome& o) {
  if (!o.decided_everywhere() || o.voltages.empty()) return std::nullopt;
  double low = o.voltages.front().frequency_hz;
  double high = low;
  for (const VoltageOutcome& v : o.voltages) {
    low = std::min(low, v.frequency_hz);
    high = std::max(high, v.frequency_hz);
  }
  return std::pair{low, high};
}

FrequencyBand oscillator_band(const std::vector<MotorOutcome>& outcomes, double yield) {
  std::vector<std::optional<std::pair<double, double>>> spans;
  for (const MotorOutcome& o : outcomes) spans.push_back(span_of(o));
  return narrowest_band(spans, yield);
}

// The band at one voltage alone (voltage index k).
FrequencyBand voltage_band(const std::vector<MotorOutcome>& outcomes, std::size_t k, double yield) {
  std::vector<std::optional<std::pair<double, double>>> spans;
  for (const MotorOutcome& o : outcomes) {
    if (o.rejected || !o.voltages[k].decided) {
      spans.emplace_back();
    } else {
      spans.emplace_back(std::pair{o.voltages[k].frequency_hz, o.voltages[k].frequency_hz});
    }
  }
  return narrowest_band(spans, yield);
}

struct VoltageStatistics {
  double amplitude_v = 0.0;
  std::size_t decided = 0;
  Distribution frequency;
  Distribution speed;
  FrequencyBand band;
};

std::vector<VoltageStatistics> per_voltage(const PopulationStudy& study, const std::vector<MotorOutcome>& outcomes,
                                           double yield) {
  std::vector<VoltageStatistics> stats;
  for (std::size_t k = 0; k < study.voltages.size(); ++k) {
    std::vector<double> frequencies;
    std::vector<double> speeds;
    for (const MotorOutcome& o : outcomes) {
      if (o.rejected || !o.voltages[k].decided) continue;
      frequencies.push_back(o.voltages[k].frequency_hz);
      speeds.push_back(o.voltages[k].speed_mm_s);
    }
    VoltageStatistics s;
    s.amplitude_v = study.voltages[k];
    s.decided = frequencies.size();
    s.frequency = describe_distribution(frequencies);
    s.speed = describe_distribution(speeds);
    s.band = voltage_band(outcomes, k, yield);
    stats.push_back(s);
  }
  return stats;
}

Json distribution_json(const Distribution& d) {
  if (d.count == 0) return nullptr;
  return Json{{"min", d.min}, {"p5", d.p5}, {"p50", d.p50}, {"p95", d.p95}, {"max", d.max}};
}

Json band_json(const FrequencyBand& b) {
  Json j;
  j["reached"] = b.reached;
  j["low_hz"] = b.reached ? Json(b.low_hz) : Json(nullptr);
  j["high_hz"] = b.reached ? Json(b.high_hz) : Json(nullptr);
  j["width_hz"] = b.reached ? Json(b.high_hz - b.low_hz) : Json(nullptr);
  j["motors_needed"] = b.needed;
  j["motors_covered"] = b.covered;
  return j;
}

std::size_t count_status(const std::vector<MotorOutcome>& outcomes, const std::string& status) {
  return static_cast<std::size_t>(
      std::count_if(outcomes.begin(), outcomes.end(), [&](const MotorOutcome& o) { return o.status() == status; }));
}

}  // namespace

std::string population_csv_header(const PopulationStudy& study) {
  std::string h = "motor,status";
  for (const ParameterSpread& s : study.spreads) h += "," + s.spec->name();
  for (double v : study.voltages) {
    const std::string l = voltage_label(v);
    h += ",frequency_hz_" + l + ",speed_mm_s_" + l + ",peak_frequency_hz_" + l;
  }
  return h + ",note\n";
}

std::string population_csv_row(const PopulationStudy& study, const MotorOutcome& o) {
  std::string row = std::to_string(o.motor) + "," + o.status();
  for (double x : o.values) row += "," + format_number(x, "%.9g");
  std::string note;
  if (o.rejected) note = o.rejection;
  for (const VoltageOutcome& v : o.voltages) {
    if (v.decided) {
      row += "," + format_number(v.frequency_hz, "%.10g") + "," + format_number(v.speed_mm_s, "%.6g") + "," +
             format_number(v.peak_frequency_hz, "%.10g");
    } else {
      row += ",,,";
      note += (note.empty() ? "" : " | ") + format_number(v.amplitude_v) + " V: " + v.reason;
    }
  }
  if (o.rejected) {
    for (std::size_t k = 0; k < study.voltages.size(); ++k) row += ",,,";  // no sweep: empty cells
  }
  return row + "," + csv_safe(note) + "\n";
}

bool population_yield_reached(const std::vector<MotorOutcome>& outcomes, double yield) {
  return oscillator_band(outcomes, yield).reached;
}

std::string population_summary_json(const PopulationStudy& study, const std::vector<MotorOutcome>& outcomes,
                                    const PopulationSummaryInputs& in) {
  Json j;
  j["config"] = in.config_path;
  j["spreads"] = in.spreads_path;
  Json varied = Json::array();
  for (const ParameterSpread& s : study.spreads) varied.push_back(s.spec->name());
  j["varied"] = varied;
  j["seed"] = study.seed;
  j["motors"] = study.motors;
  j["frequency_hz"] = in.frequency_range;
  j["load_n"] = study.load_n;
  j["margin_hz"] = study.pick.min_margin_hz;
  j["ok"] = count_status(outcomes, "ok");
  j["undecided"] = count_status(outcomes, "undecided");
  j["rejected"] = count_status(outcomes, "rejected");
  Json voltages = Json::array();
  for (const VoltageStatistics& s : per_voltage(study, outcomes, in.yield)) {
    Json v;
    v["amplitude_v"] = s.amplitude_v;
    v["decided"] = s.decided;
    v["frequency_hz"] = distribution_json(s.frequency);
    v["speed_mm_s"] = distribution_json(s.speed);
    v["band_hz"] = band_json(s.band);
    voltages.push_back(v);
  }
  j["voltages"] = voltages;
  Json range = band_json(oscillator_band(outcomes, in.yield));
  range["yield"] = in.yield;
  j["oscillator_range"] = range;
  return j.dump(2) + "\n";
}

std::string population_summary_text(const PopulationStudy& study, const std::vector<MotorOutcome>& outcomes,
                                    const PopulationSummaryInputs& in) {
  // Whole numbers as text: a 64-bit seed does not survive a double.
  std::string t = std::to_string(study.motors) + " motors, seed " + std::to_string(study.seed) + ": " +
                  std::to_string(count_status(outcomes, "ok")) + " ok, " +
                  format_numbers("%.0f undecided at some voltage, %.0f rejected draws\n",
                                 static_cast<double>(count_status(outcomes, "undecided")),
                                 static_cast<double>(count_status(outcomes, "rejected")));
  t += "   V  motors   operating frequency (Hz): min      p5     p50     p95     max"
       "   speed (mm/s): min     p5    p50    p95    max\n";
  for (const VoltageStatistics& s : per_voltage(study, outcomes, in.yield)) {
    t += format_numbers("%6g  %6.0f", s.amplitude_v, static_cast<double>(s.decided));
    if (s.decided == 0) {
      t += "   no motor decided\n";
      continue;
    }
    const Distribution& f = s.frequency;
    const Distribution& v = s.speed;
    t += "                         " + format_numbers("%7.0f %7.0f %7.0f %7.0f", f.min, f.p5, f.p50, f.p95) +
         format_numbers(" %7.0f              ", f.max) +
         format_numbers("%6.1f %6.1f %6.1f %6.1f", v.min, v.p5, v.p50, v.p95) + format_numbers(" %6.1f\n", v.max);
  }
  const FrequencyBand band = oscillator_band(outcomes, in.yield);
  if (band.reached) {
    t += format_numbers("oscillator range for %g %% yield (every voltage): %.0f .. %.0f Hz", 100.0 * in.yield,
                        band.low_hz, band.high_hz) +
         format_numbers(" (%.0f Hz wide), covers %.0f of %.0f motors\n", band.high_hz - band.low_hz,
                        static_cast<double>(band.covered), static_cast<double>(study.motors));
  } else {
    t += format_numbers("no oscillator range reaches %g %% yield: %.0f motors needed, ", 100.0 * in.yield,
                        static_cast<double>(band.needed)) +
         format_numbers("%.0f have an operating frequency at every voltage (see the note column)\n",
                        static_cast<double>(count_status(outcomes, "ok")));
  }
  return t;
}

}  // namespace swum::host
