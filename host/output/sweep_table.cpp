#include "output/sweep_table.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>

#include "formats/csv_table.h"
#include "formats/number_format.h"
#include "output/plot.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

std::string label_for(double amplitude_v, double load_n, bool several_loads) {
  std::string label = format_number(amplitude_v) + " V";
  if (several_loads) label += ", " + format_number(load_n) + " N";
  return label;
}

}  // namespace

std::array<double, std::size(kSizingColumns)> sizing_values(const SweepSizing& z) {
  return {z.current_rms_a_a,     z.current_rms_b_a,     z.current_peak_a_a, z.current_peak_b_a,
          z.voltage_a_v,         z.voltage_b_v,         z.power_a_w,        z.power_b_w,
          z.apparent_power_a_va, z.apparent_power_b_va, z.power_factor_a,   z.power_factor_b};
}

bool is_physical_failure(const SweepRow& row) {
  return !row.ok && (row.status == "diverged" || row.status == "fault_numerical");
}

SweepLayout sweep_layout_of(const std::vector<SweepRow>& rows) {
  SweepLayout layout;
  for (const SweepRow& row : rows) {
    layout.spread = layout.spread || row.speed_spread_mm_s >= 0.0;
    layout.time = layout.time || row.time_s.has_value();
    layout.sweep = layout.sweep || row.sweep.has_value();
    layout.electrical = layout.electrical || row.electrical.has_value() || row.stator_temperature_c.has_value();
    layout.sizing = layout.sizing || row.sizing.has_value();
  }
  return layout;
}

std::string format_sweep_header(const SweepLayout& layout) {
  std::string csv = "amplitude_v,frequency_hz,load_n,";
  if (layout.time) csv += "time_s,";
  if (layout.sweep) csv += "sweep,";
  csv += "speed_mm_s,tip_normal_um,tip_tangential_um,";
  csv += layout.spread ? "speed_spread_mm_s,status" : "status";
  if (layout.electrical) {
    for (const char* name : kElectricalColumns) csv += std::string(",") + name;
  }
  if (layout.sizing) {
    for (const char* name : kSizingColumns) csv += std::string(",") + name;
  }
  return csv + "\n";
}

std::string format_sweep_row(const SweepLayout& layout, const SweepRow& row) {
  std::string csv = format_number(row.amplitude_v) + "," + format_number(row.frequency_hz) + "," +
                    format_number(row.load_n) + ",";
  if (layout.time) {
    // Milliseconds: the resolution of the device clocks (Modbus sim_time, CAN Clock frame).
    csv += (row.time_s ? format_number(*row.time_s, "%.3f") : std::string()) + ",";
  }
  if (layout.sweep) csv += (row.sweep ? std::to_string(*row.sweep) : std::string()) + ",";
  if (row.ok) {
    csv += format_number(row.speed_mm_s) + "," + format_number(row.tip_normal_um) + "," +
           format_number(row.tip_tangential_um);
  } else {
    csv += ",,";
  }
  if (layout.spread) csv += "," + (row.ok && row.speed_spread_mm_s >= 0.0 ? format_number(row.speed_spread_mm_s) : "");
  csv += "," + row.status;
  if (layout.electrical) {
    // Measured cells only for a measured point, like the speed.
    const SweepElectrical* e = row.ok && row.electrical ? &*row.electrical : nullptr;
    for (const double* v : {e ? &e->current_a_a : nullptr, e ? &e->current_b_a : nullptr, e ? &e->phase_a_deg : nullptr,
                            e ? &e->phase_b_deg : nullptr, e ? &e->motional_phase_a_deg : nullptr,
                            e ? &e->motional_phase_b_deg : nullptr, e ? &e->power_w : nullptr}) {
      csv += "," + (v ? format_number(*v) : std::string());
    }
    csv += "," + (row.ok && row.stator_temperature_c ? format_number(*row.stator_temperature_c) : std::string());
  }
  if (layout.sizing) {
    const SweepSizing* z = row.ok && row.sizing ? &*row.sizing : nullptr;
    const std::array<double, std::size(kSizingColumns)> values = z ? sizing_values(*z)
                                                                   : std::array<double, std::size(kSizingColumns)>{};
    for (double v : values) csv += "," + (z ? format_number(v) : std::string());
  }
  return csv + "\n";
}

std::string format_sweep_csv(const std::vector<SweepRow>& rows) {
  const SweepLayout layout = sweep_layout_of(rows);
  std::string csv = format_sweep_header(layout);
  for (const SweepRow& row : rows) csv += format_sweep_row(layout, row);
  return csv;
}

std::vector<SweepRow> parse_sweep_csv(const std::string& text, const std::string& source) {
  // Cells as written (CsvLines::as_written): names and statuses are compared byte for byte.
  const CsvTable table = read_csv_table(text, CsvLines::as_written);
  if (!table.header) throw std::runtime_error(source + ": empty file");
  if (std::string retired = csv_retired_column_message(table, source); !retired.empty()) {
    throw std::runtime_error(retired);
  }
  const std::vector<std::string_view>& header = table.header->cells;
  auto column = [&](std::string_view name) { return table.column(name); };
  const int cv = column("amplitude_v"), cf = column("frequency_hz"), cl = column("load_n"), cs = column("speed_mm_s"),
            cn = column("tip_normal_um"), ct = column("tip_tangential_um"), cst = column("status"),
            csp = column("speed_spread_mm_s"), ctime = column("time_s"), csweep = column("sweep");
  int celectrical[std::size(kElectricalColumns)];
  for (std::size_t k = 0; k < std::size(kElectricalColumns); ++k) celectrical[k] = column(kElectricalColumns[k]);
  int csizing[std::size(kSizingColumns)];
  for (std::size_t k = 0; k < std::size(kSizingColumns); ++k) csizing[k] = column(kSizingColumns[k]);
  if (cv < 0 || cf < 0 || cs < 0) {
    throw std::runtime_error(source + ": not a sweep table (header needs amplitude_v, frequency_hz, speed_mm_s)");
  }
  std::vector<SweepRow> rows;
  for (const CsvRow& csv_row : table.rows) {
    const int number = csv_row.line;
    const std::vector<std::string_view>& cells = csv_row.cells;
    if (cells.size() != header.size()) {
      throw std::runtime_error(source + " line " + std::to_string(number) + ": " + std::to_string(cells.size()) +
                               " cells, the header has " + std::to_string(header.size()));
    }
    auto cell = [&](int c) { return c >= 0 ? std::string(cells[static_cast<std::size_t>(c)]) : std::string(); };
    auto where = [&](int c) {
      return source + " line " + std::to_string(number) + " column " + std::string(header[static_cast<std::size_t>(c)]);
    };
    auto value = [&](int c) { return parse_finite_number(cell(c), where(c)); };
    SweepRow row;
    row.amplitude_v = value(cv);
    row.frequency_hz = value(cf);
    row.load_n = cl >= 0 ? value(cl) : 0.0;
    if (ctime >= 0 && !cell(ctime).empty()) {
      row.time_s = value(ctime);
      if (*row.time_s < 0.0) throw std::runtime_error(where(ctime) + ": must be >= 0");
    }
    if (csweep >= 0 && !cell(csweep).empty()) {
      const double id = value(csweep);
      if (id < 0.0 || id != std::floor(id) || id > 1e9) {
        throw std::runtime_error(where(csweep) + ": " + cell(csweep) + " is not a sweep id (a whole number >= 0)");
      }
      row.sweep = static_cast<int>(id);
    }
    row.status = cst >= 0 ? cell(cst) : "ok";
    // "unsettled": the model's windows had not quite agreed, the values are still its best.
    row.ok = (row.status == "ok" || row.status == "unsettled") && !cell(cs).empty();
    if (row.ok) {
      row.speed_mm_s = value(cs);
      if (cn >= 0 && !cell(cn).empty()) row.tip_normal_um = value(cn);
      if (ct >= 0 && !cell(ct).empty()) row.tip_tangential_um = value(ct);
      if (csp >= 0 && !cell(csp).empty()) row.speed_spread_mm_s = value(csp);
      constexpr std::size_t kValues = std::size(kElectricalColumns) - 1;  // then the temperature
      if (std::all_of(celectrical, celectrical + kValues, [&](int c) { return !cell(c).empty(); })) {
        row.electrical = SweepElectrical{value(celectrical[0]), value(celectrical[1]), value(celectrical[2]),
                                         value(celectrical[3]), value(celectrical[4]), value(celectrical[5]),
                                         value(celectrical[6])};
      }
      if (!cell(celectrical[kValues]).empty()) row.stator_temperature_c = value(celectrical[kValues]);
      if (std::all_of(std::begin(csizing), std::end(csizing), [&](int c) { return !cell(c).empty(); })) {
        double v[std::size(kSizingColumns)];
        for (std::size_t k = 0; k < std::size(kSizingColumns); ++k) v[k] = value(csizing[k]);
        row.sizing = SweepSizing{v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9], v[10], v[11]};
      }
    }
    rows.push_back(row);
  }
  return rows;
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
    const auto key = versus_frequency ? std::make_pair(row.amplitude_v, row.load_n) : std::make_pair(0.0, row.load_n);
    PlotSeries& series = curves[key];
    if (series.label.empty()) {
      series.label = versus_frequency ? label_for(row.amplitude_v, row.load_n, several_loads)
                                      : format_number(row.load_n) + " N load";
    }
    if (!row.ok) continue;
    series.x.push_back(versus_frequency ? row.frequency_hz / 1000.0 : row.amplitude_v);
    series.y.push_back(row.speed_mm_s);
  }

  PlotSpec spec;
  if (versus_frequency) {
    spec.title = "Mover speed vs drive frequency";
    spec.x_label = "drive frequency (kHz)";
  } else {
    spec.title = "Mover speed vs drive voltage at " + format_number(*frequencies.begin() / 1000.0) + " kHz";
    spec.x_label = "drive amplitude (V)";
  }
  spec.y_label = "mover speed (mm/s)";
  for (auto& [key, series] : curves) spec.series.push_back(std::move(series));
  write_png_plot(spec, path);
}

}  // namespace swum::host
