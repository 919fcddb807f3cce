// Fuzz target: the sweep file reader of `swum pick --sweep` (host/output/sweep_table.h
// parse_sweep_csv) and the picking rule it feeds (src/analysis/operating_point/operating_point.h
// pick_operating_point, one curve per voltage and load, as pick_command.cpp builds them).
// Invariants: the only errors are std::runtime_error and std::invalid_argument (a bad number
// cell, from parse_finite_number; `swum pick` catches both as std::exception); accepted
// rows have finite values, time_s >= 0 and sweep ids >= 0; the file format_sweep_csv writes is
// read back with the same rows and, once written, writes back identically (numbers are written
// to 6 digits, so the first write may round); every curve gets a reason, and a decided pick is a
// whole hertz at peak + margin (up to the next hertz), the margin at least one grid step, within
// the curve's measured points.
// Left out of the round trip (docs/reliability.md, findings not fixed): times of 1e15 s and more
// (format_number keeps 63 characters, so "%.3f" of a time >= 1e59 s is cut; a device clock counts
// milliseconds in 32 bits), and a status ending in '\r' (a line ending "\r\r\n": the reader
// takes off one '\r', so the status keeps the other and the row reads as not measured).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "analysis/operating_point/operating_point.h"
#include "fuzz_check.h"
#include "output/sweep_table.h"

namespace {

using swum::host::SweepRow;

std::vector<SweepRow> parse(const std::string& text, const char* source) {
  return swum::host::parse_sweep_csv(text, source);
}

void check_picks(const std::vector<SweepRow>& rows) {
  std::map<std::pair<double, double>, std::vector<swum::CurveSample>> curves;
  for (const SweepRow& r : rows) {
    if (!r.ok && !swum::host::is_physical_failure(r)) continue;  // a hole, not a collapse
    curves[{r.amplitude_v, r.load_n}].push_back({r.frequency_hz, r.speed_mm_s, r.ok, r.speed_spread_mm_s});
  }
  for (const auto& [key, samples] : curves) {
    const swum::PickResult pick = swum::pick_operating_point(samples);
    FUZZ_CHECK(!pick.reason.empty(), "a pick at %g V without a reason", key.first);
    if (!pick.decided) continue;
    FUZZ_CHECK(std::any_of(samples.begin(), samples.end(),
                           [&](const swum::CurveSample& s) { return s.ok && s.frequency_hz >= pick.frequency_hz; }),
               "picked %.17g Hz, above every measured point of the curve", pick.frequency_hz);
    FUZZ_CHECK(pick.frequency_hz == std::floor(pick.frequency_hz), "picked %.17g Hz, not a whole hertz",
               pick.frequency_hz);
    FUZZ_CHECK(pick.frequency_hz - pick.peak_frequency_hz >= pick.margin_hz - 0.5,
               "picked %.17g Hz, less than the margin %g above the peak at %.17g Hz", pick.frequency_hz, pick.margin_hz,
               pick.peak_frequency_hz);
    FUZZ_CHECK(pick.grid_step_hz > 0.0 && pick.margin_hz >= pick.grid_step_hz, "margin %g, grid step %g",
               pick.margin_hz, pick.grid_step_hz);
    FUZZ_CHECK(pick.frequency_hz > pick.peak_frequency_hz, "picked %g Hz, not above the peak at %g Hz",
               pick.frequency_hz, pick.peak_frequency_hz);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(swum::fuzz::as_text(data, size));
  std::vector<SweepRow> rows;
  try {
    rows = parse(text, "fuzz.csv");
  } catch (const std::runtime_error&) {
    return 0;
  } catch (const std::invalid_argument&) {
    return 0;
  }
  bool unwritable = false;
  for (const SweepRow& r : rows) {
    FUZZ_CHECK(std::isfinite(r.amplitude_v) && std::isfinite(r.frequency_hz) && std::isfinite(r.load_n),
               "a non-finite cell");
    if (r.ok) FUZZ_CHECK(std::isfinite(r.speed_mm_s), "speed %g", r.speed_mm_s);
    if (r.time_s) FUZZ_CHECK(*r.time_s >= 0.0, "time %g", *r.time_s);
    if (r.sweep) FUZZ_CHECK(*r.sweep >= 0, "sweep %d", *r.sweep);
    unwritable = unwritable || (r.time_s && *r.time_s >= 1e15) || (!r.status.empty() && r.status.back() == '\r');
  }
  check_picks(rows);
  if (unwritable) return 0;
  const std::string written = swum::host::format_sweep_csv(rows);
  std::vector<SweepRow> again;
  try {
    again = parse(written, "written.csv");
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "the written file is refused: %s\n%s", e.what(), swum::fuzz::printable(written).c_str());
  }
  FUZZ_CHECK(again.size() == rows.size(), "%zu rows written, %zu read back", rows.size(), again.size());
  const std::string rewritten = swum::host::format_sweep_csv(again);
  FUZZ_CHECK(swum::host::format_sweep_csv(parse(rewritten, "rewritten.csv")) == rewritten,
             "a written file does not write back identically:\n%s", swum::fuzz::printable(rewritten).c_str());
  return 0;
}
