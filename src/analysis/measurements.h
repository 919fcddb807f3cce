// Measured operating points of a real motor (the input of the discrepancy workflow,
// docs/discrepancy.md): CSV with the columns vpp,frequency_hz,load_n, at least one of
// speed_mm_s, tip_normal_um, tip_tangential_um, and optionally time_s (elapsed session time).
// The text is handed in by the caller (src/ does no I/O).
#pragma once

#include <array>
#include <cstddef>
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

// The measured quantities, in column order.
enum class Quantity { speed, tip_normal, tip_tangential };
inline constexpr std::size_t kQuantityCount = 3;
inline constexpr std::array<Quantity, kQuantityCount> kQuantities{
    Quantity::speed, Quantity::tip_normal, Quantity::tip_tangential};

[[nodiscard]] std::string_view quantity_column(Quantity q);  // "speed_mm_s", ...
[[nodiscard]] std::string_view quantity_label(Quantity q);   // "speed (mm/s)", ...

struct Measurement {
  double vpp = 0.0;
  double frequency_hz = 0.0;
  double load_n = 0.0;
  std::optional<double> time_s;
  std::array<std::optional<double>, kQuantityCount> values{};  // by Quantity
  int source_line = 0;

  [[nodiscard]] const std::optional<double>& value(Quantity q) const {
    return values[static_cast<std::size_t>(q)];
  }
};

struct MeasurementSet {
  std::vector<Measurement> rows;
  std::array<bool, kQuantityCount> has_quantity{};  // the column exists
  bool has_time = false;                            // time_s given on every row
};

// Parses `text` (named `source_name` in errors). Header required (any column order; '#'
// comment and blank lines skipped). Errors (MeasurementError naming line and column): unknown,
// duplicate or missing columns, no quantity column, wrong cell count, non-numeric or
// non-finite cells, vpp < 0, frequency <= 0, negative amplitudes, time_s < 0 or empty,
// a row without any measured value, no data rows, values outside plausible ranges
// (vpp <= 10000, frequency 1000..200000 Hz, |load| <= 1000 N, time_s <= 1e8 s,
// |speed| <= 1e6 mm/s, amplitudes <= 1000 um).

[[nodiscard]] MeasurementSet parse_measurements_csv(std::string_view text,
                                                    std::string_view source_name);

// Distinct operating points (vpp, frequency_hz, load_n) among the rows.
[[nodiscard]] std::size_t count_operating_points(const MeasurementSet& set);

// Operating points only (the input of `swum synth`): the same rules, but quantity columns are
// optional and ignored.
[[nodiscard]] MeasurementSet parse_operating_points_csv(std::string_view text,
                                                        std::string_view source_name);

// The same layout (columns present in `set`; %.10g), for writing data.
[[nodiscard]] std::string format_measurements_csv(const MeasurementSet& set);

}  // namespace swum
