#include "output/reports/operating_point/band_report.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "formats/number_format.h"
#include "output/reports/report_values.h"

namespace swum::host {
namespace {

constexpr const char* kBandHeader =
    "amplitude_v,load_n,temperature_rise_k,decided,frequency_hz,speed_mm_s,peak_frequency_hz,peak_speed_mm_s,margin_hz,"
    "collapse_hz,reason,current_rms_a_a,current_rms_b_a,current_peak_a_a,current_peak_b_a,phase_a_deg,phase_b_deg,"
    "motional_phase_a_deg,motional_phase_b_deg,power_a_w,power_b_w,apparent_power_a_va,apparent_power_b_va,"
    "power_factor_a,power_factor_b\n";

// The electrical figures at the pick (band_electrical_at), in kBandHeader's order after reason.
std::vector<std::pair<const char*, double>> electrical_cells(const ElectricalReadings& e) {
  return {{"current_rms_a_a", e.rms_current_a_a},
          {"current_rms_b_a", e.rms_current_b_a},
          {"current_peak_a_a", e.peak_current_a_a},
          {"current_peak_b_a", e.peak_current_b_a},
          {"phase_a_deg", e.phase_a_deg},
          {"phase_b_deg", e.phase_b_deg},
          {"motional_phase_a_deg", e.motional_phase_a_deg},
          {"motional_phase_b_deg", e.motional_phase_b_deg},
          {"power_a_w", e.power_a_w},
          {"power_b_w", e.power_b_w},
          {"apparent_power_a_va", e.apparent_power_a_va},
          {"apparent_power_b_va", e.apparent_power_b_va},
          {"power_factor_a", e.power_factor_a},
          {"power_factor_b", e.power_factor_b}};
}

std::optional<ElectricalReadings> electrical_at_pick(const BandRow& row) {
  if (!row.pick.decided) return std::nullopt;
  return band_electrical_at(row, row.pick.frequency_hz);
}

// The reasons are prose with commas; the table has no quoting.
std::string csv_text(std::string text) {
  std::replace(text.begin(), text.end(), ',', ';');
  return text;
}

using Json = nlohmann::ordered_json;

Json range_json(const std::optional<FrequencyRange>& range) {
  if (!range) return Json(nullptr);
  return Json{{"low_hz", range->low_hz}, {"high_hz", range->high_hz}, {"width_hz", range->high_hz - range->low_hz}};
}

}  // namespace

std::string band_csv(const std::vector<BandRow>& rows) {
  std::string csv = kBandHeader;
  for (const BandRow& row : rows) {
    const PickResult& p = row.pick;
    csv += format_number(row.amplitude_v) + "," + format_number(row.load_n) + "," +
           format_number(row.temperature_rise_k) + "," + (p.decided ? "1" : "0") + ",";
    if (p.decided) {
      csv += format_number(p.frequency_hz, "%.10g") + "," + format_number(p.speed_mm_s) + "," +
             format_number(p.peak_frequency_hz, "%.10g") + "," + format_number(p.peak_speed_mm_s) + "," +
             format_number(p.margin_hz) + "," + (p.collapse_hz ? format_number(*p.collapse_hz, "%.10g") : "");
    } else {
      csv += ",,,,,";
    }
    csv += "," + csv_text(p.reason);
    const std::optional<ElectricalReadings> e = electrical_at_pick(row);
    for (const auto& [name, value] : electrical_cells(e.value_or(ElectricalReadings{}))) {
      csv += "," + (e ? format_number(value) : std::string());
    }
    csv += "\n";
  }
  return csv;
}

std::string band_json(const std::vector<BandRow>& rows, const BandSummary& s, double margin_hz) {
  Json list = Json::array();
  for (const BandRow& row : rows) {
    const PickResult& p = row.pick;
    Json j;
    j["amplitude_v"] = row.amplitude_v;
    j["load_n"] = row.load_n;
    j["temperature_rise_k"] = row.temperature_rise_k;
    j["decided"] = p.decided;
    j["frequency_hz"] = number_or_null(p.decided, p.frequency_hz);
    j["speed_mm_s"] = number_or_null(p.decided, p.speed_mm_s);
    j["peak_frequency_hz"] = number_or_null(p.decided, p.peak_frequency_hz);
    j["peak_speed_mm_s"] = number_or_null(p.decided, p.peak_speed_mm_s);
    j["margin_hz"] = number_or_null(p.decided, p.margin_hz);
    j["collapse_hz"] = number_or_null(p.decided && p.collapse_hz.has_value(), p.collapse_hz.value_or(NAN));
    j["reason"] = p.reason;
    const std::optional<ElectricalReadings> e = electrical_at_pick(row);
    if (e) {
      Json electrical;
      for (const auto& [name, value] : electrical_cells(*e)) electrical[name] = value;
      j["electrical"] = electrical;
    } else {
      j["electrical"] = nullptr;
    }
    list.push_back(j);
  }
  Json j;
  j["min_margin_hz"] = margin_hz;
  j["decided"] = s.decided;
  j["undecided"] = s.undecided;
  j["band"] = range_json(s.band);
  j["peak"] = range_json(s.peak);
  j["rows"] = list;
  return j.dump(2) + "\n";
}

std::string band_text(const std::vector<BandRow>& rows, const BandSummary& s, double margin_hz,
                      const std::string& out_path) {
  std::string t;
  if (s.band) {
    t += format_numbers("operating band %.0f .. %.0f Hz (%.0f Hz wide): the picked frequencies", s.band->low_hz,
                        s.band->high_hz, s.band->high_hz - s.band->low_hz) +
         format_numbers(", margin >= %g Hz above the peak\n", margin_hz) +
         format_numbers("peak range %.0f .. %.0f Hz (%.0f Hz wide)\n", s.peak->low_hz, s.peak->high_hz,
                        s.peak->high_hz - s.peak->low_hz);
  } else {
    t += "no operating band: no row decided\n";
  }
  t += format_numbers("rows: %.0f decided, %.0f undecided\n", static_cast<double>(s.decided),
                      static_cast<double>(s.undecided));
  for (const BandRow& row : rows) {
    if (row.pick.decided) continue;
    t += format_numbers("  %g V, %g N, %g K rise: ", row.amplitude_v, row.load_n, row.temperature_rise_k) +
         row.pick.reason + "\n";
  }
  if (!out_path.empty()) t += "rows -> " + out_path + "\n";
  return t;
}

}  // namespace swum::host
