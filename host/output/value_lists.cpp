#include "output/value_lists.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "formats/name_list.h"

namespace swum::host {
namespace {

// Built by append: GCC 12 reports a false -Wrestrict for "'" + std::string(...).
std::string quoted(std::string_view text) {
  std::string result;
  result.reserve(text.size() + 2);
  result.append(1, '\'').append(text).append(1, '\'');
  return result;
}

std::string_view trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
  return text;
}

}  // namespace

double parse_finite_number(std::string_view text, std::string_view what) {
  const std::string_view trimmed = trim(text);
  double value = 0.0;
  const char* first = trimmed.data();
  const char* last = trimmed.data() + trimmed.size();
  if (!trimmed.empty() && *first == '+') ++first;  // from_chars rejects a leading '+'
  const auto [end, error] = std::from_chars(first, last, value);
  if (trimmed.empty() || error != std::errc() || end != last) {
    throw std::invalid_argument(std::string(what) + ": " + quoted(text) + " is not a number");
  }
  if (!std::isfinite(value)) {
    throw std::invalid_argument(std::string(what) + ": " + quoted(text) + " is not finite");
  }
  return value;
}

std::vector<double> parse_number_list(std::string_view text, std::string_view what) {
  std::vector<double> values;
  for (const std::string_view entry : split_comma_list(text)) {
    if (entry.empty()) throw std::invalid_argument(std::string(what) + ": empty entry in list " + quoted(text));
    values.push_back(parse_finite_number(entry, what));
  }
  return values;
}

std::vector<double> parse_range_or_value(std::string_view text, std::string_view what, std::size_t max_points) {
  const std::size_t first_colon = text.find(':');
  if (first_colon == std::string_view::npos) return {parse_finite_number(text, what)};
  const std::size_t second_colon = text.find(':', first_colon + 1);
  if (second_colon == std::string_view::npos || text.find(':', second_colon + 1) != std::string_view::npos) {
    throw std::invalid_argument(std::string(what) + ": " + quoted(text) + " is not of the form START:STOP:STEP");
  }
  const double start = parse_finite_number(text.substr(0, first_colon), what);
  const double stop = parse_finite_number(text.substr(first_colon + 1, second_colon - first_colon - 1), what);
  const double step = parse_finite_number(text.substr(second_colon + 1), what);
  if (step <= 0.0) {
    throw std::invalid_argument(std::string(what) + ": STEP in " + quoted(text) + " must be > 0");
  }
  if (stop < start) {
    throw std::invalid_argument(std::string(what) + ": STOP in " + quoted(text) + " is below START");
  }
  const double count = std::floor((stop - start) / step + 1e-6) + 1.0;
  if (count > static_cast<double>(max_points)) {
    throw std::invalid_argument(std::string(what) + ": " + quoted(text) + " has more than " +
                                std::to_string(max_points) + " points");
  }
  std::vector<double> values;
  values.reserve(static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < static_cast<std::size_t>(count); ++i) {
    values.push_back(start + static_cast<double>(i) * step);
  }
  return values;
}

}  // namespace swum::host
