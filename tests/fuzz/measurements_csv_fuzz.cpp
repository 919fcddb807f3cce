// Fuzz target: the measurement CSV reader (src/analysis/measurements/measurements.h) behind `swum discrepancy`,
// `swum synth` (operating points) and the sweep/log files read as measurements.
// Invariants, for parse_measurements_csv and parse_operating_points_csv: the only error is
// MeasurementError; an accepted set has rows, every value finite and inside the documented
// plausible ranges, measurement_note and count_operating_points answer; writing it
// (format_measurements_csv) gives a file the reader accepts and that writes back identically.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "analysis/measurements/measurements.h"
#include "fuzz_check.h"

namespace {

using swum::MeasurementSet;

void check_values(const MeasurementSet& set) {
  FUZZ_CHECK(!set.rows.empty(), "accepted without rows");
  for (const swum::Measurement& m : set.rows) {
    FUZZ_CHECK(std::isfinite(m.amplitude_v) && m.amplitude_v >= 0.0 && m.amplitude_v <= 10000.0, "amplitude_v %g",
               m.amplitude_v);
    FUZZ_CHECK(m.frequency_hz >= 1000.0 && m.frequency_hz <= 200000.0, "frequency %g", m.frequency_hz);
    FUZZ_CHECK(std::abs(m.load_n) <= 1000.0, "load %g", m.load_n);
    FUZZ_CHECK(set.has_time == m.time_s.has_value(), "time_s on some rows only");
    if (m.time_s) FUZZ_CHECK(*m.time_s >= 0.0 && *m.time_s <= 1e8, "time %g", *m.time_s);
    if (m.sweep) FUZZ_CHECK(*m.sweep >= 0, "sweep %d", *m.sweep);
    for (const auto& v : m.values) {
      if (v) FUZZ_CHECK(std::isfinite(*v) && std::abs(*v) <= 1e6, "value %g", *v);
    }
  }
  (void)swum::measurement_note(set);
  FUZZ_CHECK(swum::count_operating_points(set) >= 1, "no operating point among %zu rows", set.rows.size());
}

template <typename Parse>
void check(std::string_view text, Parse parse) {
  MeasurementSet set;
  try {
    set = parse(text, "fuzz.csv");
  } catch (const swum::MeasurementError&) {
    return;
  }
  check_values(set);
  const std::string written = swum::format_measurements_csv(set);
  MeasurementSet again;
  try {
    again = parse(written, "written.csv");
  } catch (const swum::MeasurementError& e) {
    FUZZ_CHECK(false, "the written file is refused: %s\n%s", e.what(), written.c_str());
  }
  FUZZ_CHECK(again.rows.size() == set.rows.size(), "%zu rows written, %zu read back", set.rows.size(),
             again.rows.size());
  FUZZ_CHECK(swum::format_measurements_csv(again) == written, "writing what was read back differs");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = swum::fuzz::as_text(data, size);
  check(text, swum::parse_measurements_csv);
  check(text, swum::parse_operating_points_csv);
  return 0;
}
