#include "analysis/measurements.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <set>

#include "config/csv_cells.h"

namespace swum {
namespace {

// Column identifiers: the three operating-point columns, time, then the quantities.
enum Column : int { kVpp, kFrequency, kLoad, kTime, kSpeed, kNormal, kTangential, kColumnCount };
constexpr std::array<std::string_view, kColumnCount> kNames{
    "vpp", "frequency_hz", "load_n", "time_s", "speed_mm_s", "tip_normal_um", "tip_tangential_um"};
struct PlausibleRange {
  double max_abs;
  const char* text;
};
constexpr std::array<PlausibleRange, 7> kPlausibleRange{{
    {10000.0, "0..10000 Vpp"},
    {200000.0, "1000..200000 Hz"},
    {1000.0, "-1000..1000 N"},
    {1.0e8, "0..1e8 s"},
    {1.0e6, "-1e6..1e6 mm/s"},
    {1000.0, "0..1000 um"},
    {1000.0, "0..1000 um"},
}};
std::string format_cell(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

class Reader {
 public:
  explicit Reader(std::string_view source) : source_(source) {}

  [[noreturn]] void fail(int line, int column, const std::string& what) const {
    std::string message(source_);
    message += ":" + std::to_string(line);
    if (column > 0) message += ":" + std::to_string(column);
    throw MeasurementError(message + ": " + what);
  }

  std::optional<double> number(std::string_view cell, int line, int column,
                               std::string_view name) const {
    if (cell.empty()) return std::nullopt;
    double value = 0.0;
    if (const char* problem = parse_number_cell(cell, value)) {
      fail(line, column, "column " + std::string(name) + ": '" + printable_cell(cell) + "' " + problem);
    }
    return value;
  }

 private:
  std::string_view source_;
};

}  // namespace

std::string_view quantity_column(Quantity q) {
  return kNames[static_cast<std::size_t>(kSpeed) + static_cast<std::size_t>(q)];
}

std::string_view quantity_label(Quantity q) {
  switch (q) {
    case Quantity::speed: return "speed (mm/s)";
    case Quantity::tip_normal: return "tip normal amplitude (um)";
    case Quantity::tip_tangential: return "tip tangential amplitude (um)";
  }
  return "";
}

namespace {

MeasurementSet parse_csv(std::string_view text, std::string_view source, bool need_values) {
  const Reader reader(source);
  std::array<int, kColumnCount> index;
  index.fill(-1);
  std::size_t header_cells = 0;
  bool have_header = false;
  MeasurementSet set;
  int line_number = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t newline = text.find('\n', start);
    const std::string_view raw = text.substr(
        start, newline == std::string_view::npos ? std::string_view::npos : newline - start);
    start = newline == std::string_view::npos ? text.size() + 1 : newline + 1;
    ++line_number;
    const std::string_view line = trim_cell(raw);
    if (line.empty() || line.front() == '#') continue;
    const std::vector<std::string_view> cells = split_csv_cells(line);
    const int n = static_cast<int>(cells.size());
    if (!have_header) {
      have_header = true;
      header_cells = cells.size();
      for (int c = 0; c < n; ++c) {
        int k = 0;
        while (k < kColumnCount && kNames[static_cast<std::size_t>(k)] != cells[static_cast<std::size_t>(c)]) ++k;
        if (k == kColumnCount) {
          reader.fail(line_number, c + 1,
                      "unknown column '" + std::string(cells[static_cast<std::size_t>(c)]) +
                          "' (known: vpp, frequency_hz, load_n, time_s, speed_mm_s, "
                          "tip_normal_um, tip_tangential_um)");
        }
        if (index[static_cast<std::size_t>(k)] >= 0) {
          reader.fail(line_number, c + 1, "column " + std::string(kNames[static_cast<std::size_t>(k)]) + " appears twice");
        }
        index[static_cast<std::size_t>(k)] = c;
      }
      for (int k : {kVpp, kFrequency, kLoad}) {
        if (index[static_cast<std::size_t>(k)] < 0) {
          reader.fail(line_number, n + 1, "missing column " + std::string(kNames[static_cast<std::size_t>(k)]) +
                                              " (required: vpp, frequency_hz, load_n)");
        }
      }
      for (Quantity q : kQuantities) {
        set.has_quantity[static_cast<std::size_t>(q)] = index[static_cast<std::size_t>(kSpeed) + static_cast<std::size_t>(q)] >= 0;
      }
      if (need_values && !set.has_quantity[0] && !set.has_quantity[1] && !set.has_quantity[2]) {
        reader.fail(line_number, n + 1,
                    "no measured quantity: add speed_mm_s, tip_normal_um or tip_tangential_um");
      }
      set.has_time = index[kTime] >= 0;
      continue;
    }
    if (cells.size() != header_cells) {
      reader.fail(line_number, static_cast<int>(std::min(cells.size(), header_cells)) + 1,
                  "expected " + std::to_string(header_cells) + " cells, found " +
                      std::to_string(cells.size()));
    }
    std::array<std::optional<double>, kColumnCount> v;
    for (int k = 0; k < kColumnCount; ++k) {
      const int c = index[static_cast<std::size_t>(k)];
      if (c < 0) continue;
      const auto name = kNames[static_cast<std::size_t>(k)];
      auto& value = v[static_cast<std::size_t>(k)];
      value = reader.number(cells[static_cast<std::size_t>(c)], line_number, c + 1, name);
      const bool required = k == kVpp || k == kFrequency || k == kLoad || k == kTime;
      if (required && !value) reader.fail(line_number, c + 1, "column " + std::string(name) + " is empty");
      if (!value) continue;
      if ((k == kVpp || k == kTime || k == kNormal || k == kTangential) && *value < 0.0) {
        reader.fail(line_number, c + 1, "column " + std::string(name) + ": must be >= 0");
      }
      // Ranges a measurement of this kind of motor can have (a typo like 4e10 for 40000 must
      // not run a minute of fitting on nonsense); the same frequency range as `swum sweep`.
      const auto& range = kPlausibleRange[static_cast<std::size_t>(k)];
      if (std::abs(*value) > range.max_abs || (k == kFrequency && *value < 1000.0)) {
        reader.fail(line_number, c + 1, "column " + std::string(name) + ": " + format_cell(*value) +
                                            " is outside " + range.text);
      }
    }
    Measurement m;
    m.vpp = *v[kVpp];
    m.frequency_hz = *v[kFrequency];
    m.load_n = *v[kLoad];
    m.time_s = v[kTime];
    bool any = false;
    for (Quantity q : kQuantities) {
      const auto& value = v[static_cast<std::size_t>(kSpeed) + static_cast<std::size_t>(q)];
      m.values[static_cast<std::size_t>(q)] = value;
      any |= value.has_value();
    }
    if (need_values && !any) reader.fail(line_number, 0, "no measured value in this row");
    m.source_line = line_number;
    set.rows.push_back(m);
  }
  if (!have_header) reader.fail(1, 0, "no header line (the file is empty)");
  if (set.rows.empty()) reader.fail(line_number, 0, "no data rows");
  return set;
}

}  // namespace

MeasurementSet parse_measurements_csv(std::string_view text, std::string_view source) {
  return parse_csv(text, source, true);
}

MeasurementSet parse_operating_points_csv(std::string_view text, std::string_view source) {
  MeasurementSet set = parse_csv(text, source, false);
  for (Measurement& m : set.rows) m.values = {};
  set.has_quantity = {};
  return set;
}

std::string format_measurements_csv(const MeasurementSet& set) {
  std::string out = "vpp,frequency_hz,load_n";
  if (set.has_time) out += ",time_s";
  for (Quantity q : kQuantities) {
    if (set.has_quantity[static_cast<std::size_t>(q)]) out += "," + std::string(quantity_column(q));
  }
  out += "\n";
  char buffer[64];
  auto add = [&](double value) {
    std::snprintf(buffer, sizeof buffer, "%.10g", value);
    out += buffer;
  };
  for (const Measurement& m : set.rows) {
    add(m.vpp);
    out += ",";
    add(m.frequency_hz);
    out += ",";
    add(m.load_n);
    if (set.has_time) {
      out += ",";
      add(m.time_s.value_or(0.0));
    }
    for (Quantity q : kQuantities) {
      if (!set.has_quantity[static_cast<std::size_t>(q)]) continue;
      out += ",";
      if (m.value(q)) add(*m.value(q));
    }
    out += "\n";
  }
  return out;
}

std::size_t count_operating_points(const MeasurementSet& set) {
  std::set<std::array<double, 3>> points;
  for (const Measurement& m : set.rows) points.insert({m.vpp, m.frequency_hz, m.load_n});
  return points.size();
}

}  // namespace swum
