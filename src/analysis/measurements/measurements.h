// Measured operating points of a real motor (the input of the discrepancy workflow,
// docs/discrepancy.md): CSV with the columns amplitude_v,frequency_hz,load_n, at least one of
// speed_mm_s, tip_normal_um, tip_tangential_um, and optionally time_s (elapsed session time)
// and sweep (id of the continuous sweep a row belongs to). The outputs of `swum sweep` and
// `swum log` are read as they are (docs/host.md, "Sweep and log files as measurements"):
// their informational columns are ignored, rows the device did not measure are left out and
// counted by reason.
// The text is handed in by the caller (src/ does no I/O).
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace swum {

// A malformed measurements file: "SOURCE:LINE:COLUMN: what" (COLUMN = 1-based cell index).
class MeasurementError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The one-word status a sweep row records for a device fault (host/output/sweep_table.h):
// fault_command_timeout, fault_numerical, fault_<code> for a code this build does not know. The
// device sweep writes it and the measurements reader reads it back: one vocabulary.
[[nodiscard]] std::string fault_status_word(int fault_code);

// The measured quantities, in column order.
enum class Quantity { speed, tip_normal, tip_tangential };
inline constexpr std::size_t kQuantityCount = 3;
inline constexpr std::array<Quantity, kQuantityCount> kQuantities{Quantity::speed, Quantity::tip_normal,
                                                                  Quantity::tip_tangential};

[[nodiscard]] std::string_view quantity_column(Quantity q);  // "speed_mm_s", ...
[[nodiscard]] std::string_view quantity_label(Quantity q);   // "speed (mm/s)", ...
// "speed" or "speed_mm_s" -> Quantity::speed (likewise tip_normal, tip_tangential); nullopt if
// unknown.
[[nodiscard]] std::optional<Quantity> quantity_from_name(std::string_view name);

struct Measurement {
  double amplitude_v = 0.0;
  double frequency_hz = 0.0;
  double load_n = 0.0;
  std::optional<double> time_s;
  // Continuous sweep this row belongs to (column `sweep`): rows of one sweep were taken one
  // after the other in session order without stopping the drive, so each starts from the
  // state the previous one left (docs/discrepancy.md, "What a prediction of a measured point
  // is"). Absent: the point was approached from rest.
  std::optional<int> sweep;
  std::array<std::optional<double>, kQuantityCount> values{};  // by Quantity
  int source_line = 0;

  [[nodiscard]] const std::optional<double>& value(Quantity q) const { return values[static_cast<std::size_t>(q)]; }
};

struct MeasurementSet {
  std::vector<Measurement> rows;
  std::array<bool, kQuantityCount> has_quantity{};  // the column exists
  bool has_time = false;                            // time_s given on every row
  bool has_sweep = false;                           // the sweep column exists

  // What the parser read past, so a command can say so in one line (measurement_note):
  std::vector<std::string> ignored_columns;      // informational columns, never read
  int skipped_rows = 0;                          // rows left out of `rows` ...
  std::map<std::string, int> skipped_by_reason;  // ... by reason (a status word, "drive_off", ...)
  std::string time_column;                       // the column time_s came from, if any
  bool sweeps_from_state = false;                // sweep ids = running stretches of a log
};

// Parses `text` (named `source_name` in errors). Header required (any column order; '#'
// comment and blank lines skipped). Errors (MeasurementError naming line and column): unknown,
// duplicate or missing columns, no quantity column, wrong cell count, non-numeric or
// non-finite cells, amplitude_v < 0, frequency <= 0, negative amplitudes, time_s < 0 or empty,
// sweep not a whole number >= 0, a row without any measured value, no data rows, values
// outside plausible ranges (amplitude_v <= 10000, frequency 1000..200000 Hz, |load| <= 1000 N,
// time_s <= 1e8 s, |speed| <= 1e6 mm/s, amplitudes <= 1000 um), an unknown `status` word or
// `state` value, no row left to use.
//
// Sweep and log files: `device_time_s` is read as time_s (the device clock); the columns in
// kInformationalColumns are ignored (listed in ignored_columns). Rows are left out (counted in
// skipped_by_reason) when `status` is not ok/unsettled (diverged, fault_numerical,
// fault_command_timeout, fault_<n>, timeout, no_drive: the reason is the status word), when a
// `state` column says the drive was not running (state 0 or amplitude_v 0: "drive_off"; state 2: the
// fault, named from `fault_code` as in a sweep's status), or when `phase_deg` is not 90
// ("phase_not_90_deg": predictions are made at 90 deg). Without a `sweep` column, a file with
// a `state` column (a log) gets sweep ids: each stretch of consecutive rows used is one sweep.
inline constexpr std::array<std::string_view, 27> kInformationalColumns{
    "speed_spread_mm_s", "host_time_s", "position_mm", "last_reject", "lateness_p99_us", "lateness_max_us", "overruns",
    "current_a_a", "current_b_a", "phase_a_deg", "phase_b_deg", "motional_phase_a_deg", "motional_phase_b_deg",
    "power_w", "stator_temperature_c",
    // a model sweep's sizing columns
    "current_rms_a_a", "current_rms_b_a", "current_peak_a_a", "current_peak_b_a", "voltage_a_v", "voltage_b_v",
    "power_a_w", "power_b_w", "apparent_power_a_va", "apparent_power_b_va", "power_factor_a", "power_factor_b"};

[[nodiscard]] MeasurementSet parse_measurements_csv(std::string_view text, std::string_view source_name);

// One line for the user about what was read past ("note: ignored columns a, b; 3 rows left out
// (2 fault_numerical, 1 timeout)"), or "" when the whole file was used as it is.
[[nodiscard]] std::string measurement_note(const MeasurementSet& set);

// Distinct operating points (amplitude_v, frequency_hz, load_n) among the rows.
[[nodiscard]] std::size_t count_operating_points(const MeasurementSet& set);

// Operating points only (the input of `swum synth`): the same rules, but quantity columns are
// optional and ignored.
[[nodiscard]] MeasurementSet parse_operating_points_csv(std::string_view text, std::string_view source_name);

// The same layout (columns present in `set`; %.10g), for writing data.
[[nodiscard]] std::string format_measurements_csv(const MeasurementSet& set);
// Its header line and one row line (each with its '\n'), for files written row by row.
[[nodiscard]] std::string format_measurements_header(const MeasurementSet& set);
[[nodiscard]] std::string format_measurement_row(const MeasurementSet& set, const Measurement& m);

}  // namespace swum
