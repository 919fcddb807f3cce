#include "analysis/measurements/measurements.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <set>

#include "codes.h"  // protocol/: the state and fault codes a log file records
#include "formats/csv_cells.h"
#include "formats/csv_table.h"
#include "formats/number_format.h"

namespace swum {
namespace {

// Column identifiers: the three operating-point columns, time, then the quantities.
enum Column : int { kAmplitudeV, kFrequency, kLoad, kTime, kSpeed, kNormal, kTangential, kSweep, kColumnCount };
constexpr std::array<std::string_view, kColumnCount> kNames{
    "amplitude_v", "frequency_hz", "load_n", "time_s", "speed_mm_s", "tip_normal_um", "tip_tangential_um", "sweep"};
struct PlausibleRange {
  double max_abs;
  const char* text;
};
constexpr std::array<PlausibleRange, kColumnCount> kPlausibleRange{{
    {10000.0, "0..10000 V"},
    {200000.0, "1000..200000 Hz"},
    {1000.0, "-1000..1000 N"},
    {1.0e8, "0..1e8 s"},
    {1.0e6, "-1e6..1e6 mm/s"},
    {1000.0, "0..1000 um"},
    {1000.0, "0..1000 um"},
    {1.0e9, "0..1000000000"},
}};
std::string format_cell(double value) { return format_number(value, "%g"); }

class Reader {
 public:
  explicit Reader(std::string_view source) : source_(source) {}

  [[noreturn]] void fail(int line, int column, const std::string& what) const {
    throw MeasurementError(csv_message(source_, line, column, what));
  }

  std::optional<double> number(std::string_view cell, int line, int column, std::string_view name) const {
    std::optional<double> value;
    if (const std::string problem = csv_number_problem(cell, name, value); !problem.empty()) {
      fail(line, column, problem);
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

std::optional<Quantity> quantity_from_name(std::string_view name) {
  constexpr std::array<std::string_view, kQuantityCount> kShort{"speed", "tip_normal", "tip_tangential"};
  for (Quantity q : kQuantities) {
    if (name == quantity_column(q) || name == kShort[static_cast<std::size_t>(q)]) return q;
  }
  return std::nullopt;
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

// Columns of sweep and log files (docs/host.md) that decide whether a row is used.
enum class Control { status, state, fault_code, phase };
constexpr std::array<std::pair<std::string_view, Control>, 4> kControlNames{{
    {"status", Control::status},
    {"state", Control::state},
    {"fault_code", Control::fault_code},
    {"phase_deg", Control::phase},
}};
constexpr std::string_view kDeviceTime = "device_time_s";  // `swum log`: the device clock

// Status words of `swum sweep` (host/output/sweep_table.h): rows with these are used ...
constexpr std::array<std::string_view, 2> kUsedStatuses{"ok", "unsettled"};
// ... rows with these (or fault_<n>) failed or were not measured: left out and counted.
constexpr std::array<std::string_view, 5> kLeftOutStatuses{"diverged", "fault_numerical", "fault_command_timeout",
                                                           "timeout", "no_drive"};
constexpr double kPhaseToleranceDeg = 0.5;  // predictions are made at 90 deg

template <std::size_t N>
bool one_of(const std::array<std::string_view, N>& words, std::string_view word) {
  return std::find(words.begin(), words.end(), word) != words.end();
}

bool is_numbered_fault(std::string_view word) {
  constexpr std::string_view prefix = "fault_";
  if (word.size() <= prefix.size() || word.substr(0, prefix.size()) != prefix) return false;
  const std::string_view digits = word.substr(prefix.size());
  return std::all_of(digits.begin(), digits.end(), [](char ch) { return ch >= '0' && ch <= '9'; });
}

// The fault of a device as a sweep's status names it (host/device/device_sweep.cpp).
std::string known_columns() {
  std::string text = "known: ";
  for (std::string_view name : kNames) text += std::string(name) + ", ";
  text += "from sweep and log files " + std::string(kDeviceTime);
  for (const auto& [name, control] : kControlNames) text += ", " + std::string(name);
  text += "; ignored:";
  for (std::size_t k = 0; k < kInformationalColumns.size(); ++k) {
    text += (k > 0 ? ", " : " ") + std::string(kInformationalColumns[k]);
  }
  return text;
}

std::string left_out_text(const MeasurementSet& set) {
  std::vector<std::pair<std::string, int>> reasons(set.skipped_by_reason.begin(), set.skipped_by_reason.end());
  std::stable_sort(reasons.begin(), reasons.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  std::string text = std::to_string(set.skipped_rows) + (set.skipped_rows == 1 ? " row" : " rows") + " left out (";
  for (std::size_t k = 0; k < reasons.size(); ++k) {
    text += (k > 0 ? ", " : "") + std::to_string(reasons[k].second) + " " + reasons[k].first;
  }
  return text + ")";
}

MeasurementSet parse_csv(std::string_view text, std::string_view source, bool need_values) {
  const Reader reader(source);
  std::array<int, kColumnCount> index;
  index.fill(-1);
  std::array<int, kControlNames.size()> control;
  control.fill(-1);
  auto control_index = [&](Control c) { return control[static_cast<std::size_t>(c)]; };
  const CsvTable table = read_csv_table(text);
  if (!table.header) reader.fail(1, 0, "no header line (the file is empty)");
  if (std::string retired = csv_retired_column_message(table, source); !retired.empty()) {
    throw MeasurementError(retired);
  }
  MeasurementSet set;
  int stretch = -1;  // sweep id of a log's current running stretch
  bool in_stretch = false;
  {
    const int line_number = table.header->line;
    const std::vector<std::string_view>& cells = table.header->cells;
    const int n = static_cast<int>(cells.size());
    for (int c = 0; c < n; ++c) {
      const std::string_view name = cells[static_cast<std::size_t>(c)];
      const std::string twice = "column " + printable_cell(name) + " appears twice";
      int k = 0;
      while (k < kColumnCount && kNames[static_cast<std::size_t>(k)] != name) ++k;
      if (name == kDeviceTime) k = kTime;
      if (k < kColumnCount) {
        const int previous = index[static_cast<std::size_t>(k)];
        if (previous >= 0) {
          reader.fail(line_number, c + 1,
                      cells[static_cast<std::size_t>(previous)] == name
                          ? twice
                          : "columns time_s and device_time_s both give the time: keep one");
        }
        index[static_cast<std::size_t>(k)] = c;
        if (k == kTime) set.time_column = std::string(name);
        continue;
      }
      const auto found = std::find_if(kControlNames.begin(), kControlNames.end(),
                                      [&](const auto& entry) { return entry.first == name; });
      if (found != kControlNames.end()) {
        int& slot = control[static_cast<std::size_t>(found->second)];
        if (slot >= 0) reader.fail(line_number, c + 1, twice);
        slot = c;
        continue;
      }
      if (one_of(kInformationalColumns, name)) {
        if (std::find(set.ignored_columns.begin(), set.ignored_columns.end(), name) != set.ignored_columns.end()) {
          reader.fail(line_number, c + 1, twice);
        }
        set.ignored_columns.emplace_back(name);
        continue;
      }
      reader.fail(line_number, c + 1, "unknown column '" + printable_cell(name) + "' (" + known_columns() + ")");
    }
    for (int k : {kAmplitudeV, kFrequency, kLoad}) {
      if (index[static_cast<std::size_t>(k)] < 0) {
        reader.fail(line_number, n + 1,
                    "missing column " + std::string(kNames[static_cast<std::size_t>(k)]) +
                        " (required: amplitude_v, frequency_hz, load_n)");
      }
    }
    for (Quantity q : kQuantities) {
      set.has_quantity[static_cast<std::size_t>(q)] =
          index[static_cast<std::size_t>(kSpeed) + static_cast<std::size_t>(q)] >= 0;
    }
    if (need_values && !set.has_quantity[0] && !set.has_quantity[1] && !set.has_quantity[2]) {
      reader.fail(line_number, n + 1, "no measured quantity: add speed_mm_s, tip_normal_um or tip_tangential_um");
    }
    set.has_time = index[kTime] >= 0;
    set.sweeps_from_state = index[kSweep] < 0 && control_index(Control::state) >= 0;
    set.has_sweep = index[kSweep] >= 0 || set.sweeps_from_state;
  }
  for (const CsvRow& row : table.rows) {
    const int line_number = row.line;
    const std::vector<std::string_view>& cells = row.cells;
    int count_column = 0;
    if (const std::string problem = csv_cell_count_problem(table, row, count_column); !problem.empty()) {
      reader.fail(line_number, count_column, problem);
    }
    // A required cell that must hold a whole number (state, fault_code).
    auto whole_number = [&](int c, std::string_view name) {
      const auto value = reader.number(cells[static_cast<std::size_t>(c)], line_number, c + 1, name);
      if (!value) reader.fail(line_number, c + 1, "column " + std::string(name) + " is empty");
      if (*value != std::floor(*value) || std::abs(*value) > 1e9) {
        reader.fail(line_number, c + 1,
                    "column " + std::string(name) + ": " + format_cell(*value) + " is not a whole number");
      }
      return static_cast<int>(*value);
    };
    // Why the row is left out ("" = used): the sweep's status, then the drive state of a log.
    std::string reason;
    if (const int c = control_index(Control::status); c >= 0) {
      const std::string_view word = cells[static_cast<std::size_t>(c)];
      if (word.empty()) reader.fail(line_number, c + 1, "column status is empty");
      if (one_of(kLeftOutStatuses, word) || is_numbered_fault(word)) {
        reason = std::string(word);
      } else if (!one_of(kUsedStatuses, word)) {
        reader.fail(line_number, c + 1,
                    "column status: unknown status '" + printable_cell(word) +
                        "' (known: ok, unsettled, diverged, fault_numerical, "
                        "fault_command_timeout, fault_<n>, timeout, no_drive)");
      }
    }
    if (const int c = control_index(Control::state); c >= 0) {
      const int state = whole_number(c, "state");
      constexpr int kDisabled = static_cast<int>(protocol::AmpState::disabled);
      constexpr int kFault = static_cast<int>(protocol::AmpState::fault);
      if (state < kDisabled || state > kFault) {
        reader.fail(line_number, c + 1,
                    "column state: " + std::to_string(state) +
                        " is not a drive state (0 disabled, 1 running, 2 fault)");
      }
      const int fault_column = control_index(Control::fault_code);
      if (reason.empty() && state == kDisabled) reason = "drive_off";
      if (reason.empty() && state == kFault)
        reason = fault_column >= 0 ? fault_status_word(whole_number(fault_column, "fault_code")) : "fault";
    }
    std::array<std::optional<double>, kColumnCount> v;
    for (int k = 0; k < kColumnCount; ++k) {
      const int c = index[static_cast<std::size_t>(k)];
      if (c < 0) continue;
      // As the header names it (a log's device_time_s is the time).
      const std::string name = k == kTime ? set.time_column : std::string(kNames[static_cast<std::size_t>(k)]);
      auto& value = v[static_cast<std::size_t>(k)];
      value = reader.number(cells[static_cast<std::size_t>(c)], line_number, c + 1, name);
      // A log's first rows can come before the device clock does (CAN: the first Clock frame):
      // such a row is left out with its reason, not the whole file refused.
      if (k == kTime && !value && set.time_column == kDeviceTime) {
        if (reason.empty()) reason = "no_device_time";
        continue;
      }
      const bool required = k == kAmplitudeV || k == kFrequency || k == kLoad || k == kTime || k == kSweep;
      if (required && !value) reader.fail(line_number, c + 1, "column " + name + " is empty");
      if (!value) continue;
      if ((k == kAmplitudeV || k == kTime || k == kNormal || k == kTangential || k == kSweep) && *value < 0.0) {
        reader.fail(line_number, c + 1, "column " + name + ": must be >= 0");
      }
      // Ranges a measurement of this kind of motor can have (a typo like 4e10 for 40000 must
      // not run a minute of fitting on nonsense); the same frequency range as `swum sweep`.
      const auto& range = kPlausibleRange[static_cast<std::size_t>(k)];
      if (std::abs(*value) > range.max_abs || (k == kFrequency && *value < 1000.0)) {
        reader.fail(line_number, c + 1, "column " + name + ": " + format_cell(*value) + " is outside " + range.text);
      }
      if (k == kSweep && *value != std::floor(*value)) {
        reader.fail(line_number, c + 1, "column sweep: " + format_cell(*value) + " is not a whole number");
      }
    }
    if (reason.empty() && control_index(Control::state) >= 0 && *v[kAmplitudeV] == 0.0) reason = "drive_off";
    if (const int c = control_index(Control::phase); c >= 0) {
      const auto phase = reader.number(cells[static_cast<std::size_t>(c)], line_number, c + 1, "phase_deg");
      if (!phase) reader.fail(line_number, c + 1, "column phase_deg is empty");
      if (reason.empty() && std::abs(*phase - 90.0) > kPhaseToleranceDeg) reason = "phase_not_90_deg";
    }
    if (!reason.empty()) {
      ++set.skipped_rows;
      ++set.skipped_by_reason[reason];
      in_stretch = false;
      continue;
    }
    Measurement m;
    m.amplitude_v = *v[kAmplitudeV];
    m.frequency_hz = *v[kFrequency];
    m.load_n = *v[kLoad];
    m.time_s = v[kTime];
    if (v[kSweep]) m.sweep = static_cast<int>(*v[kSweep]);
    if (set.sweeps_from_state) {
      if (!in_stretch) ++stretch;
      in_stretch = true;
      m.sweep = stretch;
    }
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
  if (set.rows.empty() && set.skipped_rows > 0) {
    reader.fail(table.last_line, 0, "no usable rows: " + left_out_text(set));
  }
  if (set.rows.empty()) reader.fail(table.last_line, 0, "no data rows");
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

std::string format_measurements_header(const MeasurementSet& set) {
  std::string out = "amplitude_v,frequency_hz,load_n";
  if (set.has_time) out += ",time_s";
  if (set.has_sweep) out += ",sweep";
  for (Quantity q : kQuantities) {
    if (set.has_quantity[static_cast<std::size_t>(q)]) out += "," + std::string(quantity_column(q));
  }
  return out + "\n";
}

std::string format_measurement_row(const MeasurementSet& set, const Measurement& m) {
  std::string out;
  auto add = [&](double value) { out += format_number(value, "%.10g"); };
  add(m.amplitude_v);
  out += ",";
  add(m.frequency_hz);
  out += ",";
  add(m.load_n);
  if (set.has_time) {
    out += ",";
    add(m.time_s.value_or(0.0));
  }
  if (set.has_sweep) out += "," + std::to_string(m.sweep.value_or(0));
  for (Quantity q : kQuantities) {
    if (!set.has_quantity[static_cast<std::size_t>(q)]) continue;
    out += ",";
    if (m.value(q)) add(*m.value(q));
  }
  return out + "\n";
}

std::string format_measurements_csv(const MeasurementSet& set) {
  std::string out = format_measurements_header(set);
  for (const Measurement& m : set.rows) out += format_measurement_row(set, m);
  return out;
}

std::string measurement_note(const MeasurementSet& set) {
  std::vector<std::string> parts;
  if (!set.ignored_columns.empty()) {
    std::string part = set.ignored_columns.size() == 1 ? "ignored column" : "ignored columns";
    for (std::size_t k = 0; k < set.ignored_columns.size(); ++k) part += (k > 0 ? ", " : " ") + set.ignored_columns[k];
    parts.push_back(part + " (informational)");
  }
  if (set.time_column == kDeviceTime) parts.emplace_back("time_s from device_time_s (the device clock)");
  if (set.skipped_rows > 0) parts.push_back(left_out_text(set));
  if (parts.empty()) return "";
  std::string note = "note:";
  for (std::size_t k = 0; k < parts.size(); ++k) note += (k > 0 ? "; " : " ") + parts[k];
  return note;
}

std::size_t count_operating_points(const MeasurementSet& set) {
  std::set<std::array<double, 3>> points;
  for (const Measurement& m : set.rows) points.insert({m.amplitude_v, m.frequency_hz, m.load_n});
  return points.size();
}

std::string fault_status_word(int code) {
  if (code == static_cast<int>(protocol::FaultCode::command_timeout)) return "fault_command_timeout";
  if (code == static_cast<int>(protocol::FaultCode::numerical)) return "fault_numerical";
  return "fault_" + std::to_string(code);
}

}  // namespace swum
