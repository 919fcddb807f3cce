// Fuzz target: the host tool's command-line value forms (host/output/value_lists.h): number
// lists "A,B,C" (--amplitude-v, --load) and ranges "START:STOP:STEP" or one value (--frequency-hz).
// Invariants: the only error is std::invalid_argument; a list has one finite number per comma
// plus one, each the number parse_finite_number reads from its entry; a range has 1..max_points
// finite values, starts at START, never decreases and ends within STEP/1e6 of STOP (plus the
// rounding of the last addition); a plain value is that one number.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzz_check.h"
#include "output/value_lists.h"

namespace {

namespace host = swum::host;

void check_list(std::string_view text) {
  std::vector<double> values;
  try {
    values = host::parse_number_list(text, "--list");
  } catch (const std::invalid_argument&) {
    return;
  }
  FUZZ_CHECK(values.size() == static_cast<std::size_t>(std::count(text.begin(), text.end(), ',')) + 1,
             "'%s' gave %zu values", swum::fuzz::printable(text).c_str(), values.size());
  std::size_t start = 0;
  for (const double v : values) {
    const std::size_t comma = text.find(',', start);
    const std::string_view item = text.substr(start, comma == std::string_view::npos ? comma : comma - start);
    start = comma + 1;
    FUZZ_CHECK(std::isfinite(v) && v == host::parse_finite_number(item, "--list"), "'%s': entry '%s' read as %.17g",
               swum::fuzz::printable(text).c_str(), swum::fuzz::printable(item).c_str(), v);
  }
}

void check_range(std::string_view text) {
  constexpr std::size_t kMaxPoints = 100000;
  std::vector<double> values;
  try {
    values = host::parse_range_or_value(text, "--range", kMaxPoints);
  } catch (const std::invalid_argument&) {
    return;
  }
  const std::string shown = swum::fuzz::printable(text);
  FUZZ_CHECK(!values.empty() && values.size() <= kMaxPoints, "'%s' gave %zu values", shown.c_str(), values.size());
  const std::size_t first_colon = text.find(':');
  if (first_colon == std::string_view::npos) {
    FUZZ_CHECK(values.size() == 1 && values[0] == host::parse_finite_number(text, "--range"), "'%s' read as %.17g",
               shown.c_str(), values[0]);
    return;
  }
  const std::size_t second_colon = text.find(':', first_colon + 1);
  const double start = host::parse_finite_number(text.substr(0, first_colon), "START");
  const double stop = host::parse_finite_number(text.substr(first_colon + 1, second_colon - first_colon - 1), "STOP");
  const double step = host::parse_finite_number(text.substr(second_colon + 1), "STEP");
  FUZZ_CHECK(values.front() == start, "'%s' starts at %.17g", shown.c_str(), values.front());
  for (std::size_t i = 0; i < values.size(); ++i) {
    FUZZ_CHECK(std::isfinite(values[i]), "'%s': value %zu is %g", shown.c_str(), i, values[i]);
    if (i > 0) FUZZ_CHECK(values[i] >= values[i - 1], "'%s': value %zu decreases", shown.c_str(), i);
  }
  const double rounding = 4 * std::numeric_limits<double>::epsilon() * std::max(std::abs(start), std::abs(stop));
  FUZZ_CHECK(values.back() <= stop + step * 1e-6 + rounding, "'%s' ends at %.17g, beyond STOP", shown.c_str(),
             values.back());
  FUZZ_CHECK(values.back() + step > stop - rounding, "'%s' ends at %.17g, a STEP or more before STOP", shown.c_str(),
             values.back());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = swum::fuzz::as_text(data, size);
  check_list(text);
  check_range(text);
  return 0;
}
