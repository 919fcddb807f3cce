#include "formats/spread_file.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>

#include <toml++/toml.h>

#include "formats/csv_cells.h"
#include "formats/number_format.h"
#include "formats/toml_number.h"

namespace swum {
namespace {

constexpr double kMinTruncate = 0.5;  // sigmas: keeps the acceptance of a draw above 38 %
constexpr double kMaxTruncate = 10.0;
constexpr double kDefaultTruncate = 3.0;

std::string where(std::string_view source_name, const toml::source_region& region) {
  std::string s(source_name);
  if (region.begin.line > 0) s += ":" + std::to_string(region.begin.line);
  return s;
}

[[noreturn]] void fail(std::string_view source_name, const toml::node& node, const std::string& problem) {
  throw ParameterError(where(source_name, node.source()) + ": " + problem);
}

bool varying_section(std::string_view section) {
  return section == "stator" || section == "contact" || section == "mover";
}

// FNV-1a, 64 bit: a parameter's stream depends on its name only, not on the table's order nor
// on which other parameters vary.
std::uint64_t name_hash(std::string_view name) {
  std::uint64_t h = 14695981039346656037ull;
  for (const char c : name) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

class EntryReader {
 public:
  EntryReader(std::string_view source_name, const ParameterSpec& spec, const toml::table& table)
      : source_(source_name), name_(spec.name()), table_(table) {}

  // A finite number under `key`, if present.
  std::optional<double> number(std::string_view key) {
    const toml::node* node = table_.get(key);
    if (node == nullptr) return std::nullopt;
    used_.push_back(std::string(key));
    const std::optional<double> number = toml_number(*node);
    if (!number) fail(source_, *node, name_ + ": " + std::string(key) + " must be a number");
    const double v = *number;
    if (!std::isfinite(v)) fail(source_, *node, name_ + ": " + std::string(key) + " must be finite");
    return v;
  }

  std::string distribution() {
    const toml::node* node = table_.get("distribution");
    if (node == nullptr) {
      fail(source_, table_, name_ + ": distribution missing (\"normal\" or \"uniform\")");
    }
    used_.push_back("distribution");
    const auto* s = node->as_string();
    if (s == nullptr || (s->get() != "normal" && s->get() != "uniform")) {
      fail(source_, *node, name_ + ": unknown distribution (expected \"normal\" or \"uniform\")");
    }
    return s->get();
  }

  // Every key of the entry was read: anything else is a typo or a key of the other distribution.
  void check_no_other_keys(const std::string& distribution) {
    for (auto&& [key, node] : table_) {
      if (std::find(used_.begin(), used_.end(), key.str()) == used_.end()) {
        fail(source_, node,
             name_ + ": unknown key " + printable_cell(key.str()) + " for a " + distribution +
                 " distribution (normal: sigma or sigma_percent, truncate; uniform: min and max, "
                 "half_width or half_width_percent)");
      }
    }
  }

  // Exactly one of the keys given (values already read).
  void require_one(int given, const std::string& keys) {
    if (given != 1) fail(source_, table_, name_ + ": give exactly one of " + keys);
  }

  [[noreturn]] void fail_here(const std::string& problem) { fail(source_, table_, name_ + ": " + problem); }

 private:
  std::string_view source_;
  std::string name_;
  const toml::table& table_;
  std::vector<std::string> used_;
};

double of_nominal(EntryReader& entry, double percent, double nominal, const char* key) {
  if (nominal == 0.0) entry.fail_here(std::string(key) + " is a percentage of the nominal value, which is 0");
  return std::abs(nominal) * percent / 100.0;
}

ParameterSpread read_entry(std::string_view source_name, const ParameterSpec& spec, const toml::node& node,
                           const MotorParameters& nominal) {
  const std::string name = spec.name();
  const auto* table = node.as_table();
  if (table == nullptr) {
    fail(source_name, node,
         name + " must be a table such as { distribution = \"normal\", sigma_percent = 1 } "
                "(docs/population.md)");
  }
  ParameterSpread s;
  s.spec = &spec;
  s.nominal = spec.get(nominal);
  s.stream = name_hash(name);
  s.line = static_cast<int>(node.source().begin.line);
  EntryReader entry(source_name, spec, *table);
  const std::string distribution = entry.distribution();
  if (distribution == "normal") {
    s.distribution = SpreadDistribution::normal;
    const auto sigma = entry.number("sigma");
    const auto sigma_percent = entry.number("sigma_percent");
    const auto truncate = entry.number("truncate");
    entry.check_no_other_keys(distribution);
    entry.require_one(sigma.has_value() + sigma_percent.has_value(),
                      "sigma (" + std::string(spec.unit) + ") or sigma_percent (% of nominal)");
    const double given = sigma ? *sigma : *sigma_percent;
    if (given < 0.0) entry.fail_here("sigma " + format_number(given) + " is negative");
    s.sigma = sigma ? *sigma : of_nominal(entry, *sigma_percent, s.nominal, "sigma_percent");
    s.truncate = truncate.value_or(kDefaultTruncate);
    if (!(s.truncate >= kMinTruncate && s.truncate <= kMaxTruncate)) {
      entry.fail_here("truncate " + format_number(s.truncate) + " is outside " + format_number(kMinTruncate) + ".." +
                      format_number(kMaxTruncate) + " sigma");
    }
    s.low = s.nominal - s.truncate * s.sigma;
    s.high = s.nominal + s.truncate * s.sigma;
  } else {
    s.distribution = SpreadDistribution::uniform;
    const auto min = entry.number("min");
    const auto max = entry.number("max");
    const auto half_width = entry.number("half_width");
    const auto half_width_percent = entry.number("half_width_percent");
    entry.check_no_other_keys(distribution);
    if (min.has_value() != max.has_value()) entry.fail_here("min and max go together");
    entry.require_one(min.has_value() + half_width.has_value() + half_width_percent.has_value(),
                      "min and max (" + std::string(spec.unit) + "), half_width (" + std::string(spec.unit) +
                          ") or half_width_percent (% of nominal)");
    if (min) {
      if (*min > *max) entry.fail_here("min " + format_number(*min) + " is above max " + format_number(*max));
      s.low = *min;
      s.high = *max;
    } else {
      const double given = half_width ? *half_width : *half_width_percent;
      if (given < 0.0) entry.fail_here("half width " + format_number(given) + " is negative");
      const double w = half_width ? *half_width
                                  : of_nominal(entry, *half_width_percent, s.nominal, "half_width_percent");
      s.low = s.nominal - w;
      s.high = s.nominal + w;
    }
  }
  if (s.low < spec.min_value || s.high > spec.max_value) {
    entry.fail_here("draws range over [" + format_number(s.low) + ", " + format_number(s.high) + "] " +
                    std::string(spec.unit) + ", outside the parameter's range [" + format_number(spec.min_value) +
                    ", " + format_number(spec.max_value) + "]");
  }
  return s;
}

void check_used_by_geometry(std::string_view source_name, const toml::node& node, const ParameterSpec& spec,
                            const MotorParameters& nominal) {
  const bool from_frequencies = nominal.stator.geometry == GeometryMode::from_frequencies;
  const std::string_view key = spec.key;
  const bool explicit_only = key == "length_mm" || key == "half_height_mm";
  const bool frequencies_only = key == "target_l1_frequency_hz" || key == "target_b2_frequency_hz";
  if (spec.section != "stator") return;
  if (from_frequencies && explicit_only) {
    fail(source_name, node,
         spec.name() + " is unused: the nominal motor has geometry = \"from_frequencies\" (vary "
                       "stator.target_l1_frequency_hz / target_b2_frequency_hz instead)");
  }
  if (!from_frequencies && frequencies_only) {
    fail(source_name, node,
         spec.name() + " is unused: the nominal motor has geometry = \"explicit\" (vary stator.length_mm / "
                       "half_height_mm instead)");
  }
}

}  // namespace

std::vector<ParameterSpread> parse_parameter_spreads(std::string_view toml_text, std::string_view source_name,
                                                     const MotorParameters& nominal) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    throw ParameterError(where(source_name, e.source()) + ": TOML syntax error: " + printable_cell(e.description()));
  }
  std::map<const ParameterSpec*, ParameterSpread> found;
  for (auto&& [section_key, section_node] : root) {
    const std::string section(section_key.str());
    const auto* section_table = section_node.as_table();
    if (!varying_section(section) || section_table == nullptr) {
      fail(source_name, section_node,
           "unknown section [" + section +
               "]: spreads are tables [stator], [contact] or [mover] "
               "(the motor as built; not its model options or numerics)");
    }
    for (auto&& [key, node] : *section_table) {
      const ParameterSpec* spec = find_parameter_spec(section, key.str());
      const std::string name = section + "." + std::string(key.str());
      if (spec == nullptr) {
        fail(source_name, node, "unknown parameter " + name + " (see docs/parameters.md for the valid keys)");
      }
      if (spec->kind != ParameterKind::real) {
        fail(source_name, node, name + " is not a real-valued parameter and cannot vary");
      }
      check_used_by_geometry(source_name, node, *spec, nominal);
      found.emplace(spec, read_entry(source_name, *spec, node, nominal));
    }
  }
  std::vector<ParameterSpread> spreads;
  for (const ParameterSpec& spec : parameter_specs()) {
    if (const auto it = found.find(&spec); it != found.end()) spreads.push_back(it->second);
  }
  return spreads;
}

}  // namespace swum
