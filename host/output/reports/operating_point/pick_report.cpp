#include "output/reports/operating_point/pick_report.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "formats/number_format.h"
#include "output/reports/report_values.h"

namespace swum::host {
namespace {

// Drift: from the peak of the lowest decided voltage at the same load.
double drift_base_hz(const std::vector<VoltagePick>& picks, double load_n) {
  double base = NAN;
  double base_amplitude_v = INFINITY;
  for (const auto& p : picks) {
    if (p.result.decided && p.load_n == load_n && p.amplitude_v < base_amplitude_v) {
      base_amplitude_v = p.amplitude_v;
      base = p.result.peak_frequency_hz;
    }
  }
  return base;
}

}  // namespace

double pick_gain_percent(const PickResult& r) {
  if (!r.decided || !r.naive_speed_mm_s || std::abs(*r.naive_speed_mm_s) < 1e-9) return NAN;
  return 100.0 * (r.speed_mm_s / *r.naive_speed_mm_s - 1.0);
}

std::string pick_text(const std::vector<VoltagePick>& picks) {
  std::string out;
  for (const auto& [v, r, load_n] : picks) {
    const double base = drift_base_hz(picks, load_n);
    const std::string at = format_numbers("%6g V, %g N", v, load_n);
    if (!r.decided) {
      out += at + ": undecided: " + r.reason + "\n";
      continue;
    }
    const std::string naive = r.naive_speed_mm_s ? format_numbers("%.1f mm/s, gain %+.0f %%", *r.naive_speed_mm_s,
                                                                  pick_gain_percent(r))
                                                 : "n/a (40.4 kHz outside the sweep)";
    out += at + format_numbers(": run at %.0f Hz, %.1f mm/s", r.frequency_hz, r.speed_mm_s) +
           " (naive 40.4 kHz: " + naive + "), drift " + format_number(r.peak_frequency_hz - base, "%+.0f") + " Hz; " +
           r.reason + "\n";
  }
  return out;
}

std::string pick_json(const std::vector<VoltagePick>& picks) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const auto& [v, r, load_n] : picks) {
    const double base = drift_base_hz(picks, load_n);
    nlohmann::ordered_json j;
    j["amplitude_v"] = v;
    j["load_n"] = load_n;
    j["decided"] = r.decided;
    j["frequency_hz"] = number_or_null(r.decided, r.frequency_hz);
    j["speed_mm_s"] = number_or_null(r.decided, r.speed_mm_s);
    j["naive_speed_mm_s"] = number_or_null(r.naive_speed_mm_s.has_value(), r.naive_speed_mm_s.value_or(NAN));
    j["gain_percent"] = number_or_null(r.decided, pick_gain_percent(r));
    j["peak_frequency_hz"] = number_or_null(r.decided, r.peak_frequency_hz);
    j["drift_hz"] = number_or_null(r.decided, r.peak_frequency_hz - base);
    j["margin_hz"] = r.margin_hz;
    j["reason"] = r.reason;
    list.push_back(j);
  }
  return list.dump(2) + "\n";
}

std::string pick_schedule_csv(const std::vector<VoltagePick>& picks) {
  std::string schedule = "amplitude_v,load_n,frequency_hz\n";
  for (const auto& [v, r, load_n] : picks) {
    if (r.decided)
      schedule += format_number(v) + "," + format_number(load_n) + "," + format_number(r.frequency_hz) + "\n";
  }
  return schedule;
}

}  // namespace swum::host
