#include "formats/facts_file.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include <toml++/toml.h>

#include "formats/csv_cells.h"
#include "formats/toml_number.h"
#include "model/parameters.h"

namespace swum {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr int kMaxSearchPoints = 2000;

[[noreturn]] void fail(std::string_view source, int line, const std::string& problem) {
  throw ParameterError(std::string(source) + (line > 0 ? ":" + std::to_string(line) : "") + ": " + problem);
}

class FactReader {
 public:
  FactReader(std::string_view source, const toml::table& table, int line)
      : source_(source), table_(table), line_(line) {}

  std::optional<double> number(std::string_view key) {
    const toml::node* node = table_.get(key);
    if (node == nullptr) return std::nullopt;
    used_.insert(std::string(key));
    const std::optional<double> number = toml_number(*node);
    if (!number) fail(source_, line_, std::string(key) + ": expected a number");
    const double v = *number;
    if (!std::isfinite(v)) fail(source_, line_, std::string(key) + ": not a finite number");
    return v;
  }

  double required(std::string_view key, std::string_view kind) {
    const std::optional<double> v = number(key);
    if (!v) fail(source_, line_, std::string(kind) + " fact needs " + std::string(key));
    return *v;
  }

  template <std::size_t N>
  void numbers(std::string_view key, std::array<double, N>& out) {
    const toml::node* node = table_.get(key);
    if (node == nullptr) return;
    used_.insert(std::string(key));
    const auto* array = node->as_array();
    if (array == nullptr || array->size() != N) {
      fail(source_, line_, std::string(key) + ": expected an array of " + std::to_string(N) + " numbers");
    }
    for (std::size_t k = 0; k < N; ++k) {
      const std::optional<double> number = toml_number(*array->get(k));
      if (!number) fail(source_, line_, std::string(key) + ": expected an array of " + std::to_string(N) + " numbers");
      out[k] = *number;
      if (!std::isfinite(out[k])) fail(source_, line_, std::string(key) + ": not a finite number");
    }
  }

  std::optional<std::string> text(std::string_view key) {
    const toml::node* node = table_.get(key);
    if (node == nullptr) return std::nullopt;
    used_.insert(std::string(key));
    const auto* s = node->as_string();
    if (s == nullptr) fail(source_, line_, std::string(key) + ": expected a string");
    return s->get();
  }

  // Before anything is read: a misspelt key is named as such, not as the key it was meant to be.
  void check_known(const std::vector<std::string_view>& allowed) const {
    std::string list;
    for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    for (const auto& [key, node] : table_) {
      if (std::find(allowed.begin(), allowed.end(), key.str()) == allowed.end()) {
        fail(source_, line_, "unknown key '" + printable_cell(key.str()) + "' (this kind takes: " + list + ")");
      }
    }
  }

  void range(std::string_view key, double value, double lo, double hi) const {
    if (!(value >= lo && value <= hi)) {
      fail(source_, line_,
           std::string(key) + " = " + std::to_string(value) + " outside [" + std::to_string(lo) + ", " +
               std::to_string(hi) + "]");
    }
  }

 private:
  std::string_view source_;
  const toml::table& table_;
  int line_;
  std::set<std::string> used_;
};

}  // namespace

double Fact::centre() const {
  if (target) return *target;
  if (std::isfinite(min) && std::isfinite(max)) return 0.5 * (min + max);
  return std::isfinite(min) ? min : max;
}

std::string_view Fact::unit() const {
  switch (kind) {
    case FactKind::peak_frequency: return "Hz";
    case FactKind::dead_zone_onset: return "V";
    case FactKind::saturation_ratio: return "";
    case FactKind::speed: return "mm/s";
  }
  return "";
}

std::string_view fact_kind_name(FactKind kind) {
  switch (kind) {
    case FactKind::peak_frequency: return "peak_frequency";
    case FactKind::dead_zone_onset: return "dead_zone_onset";
    case FactKind::saturation_ratio: return "saturation_ratio";
    case FactKind::speed: return "speed";
  }
  return "";
}

std::vector<Fact> parse_facts(std::string_view toml_text, std::string_view source_name) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    fail(source_name, static_cast<int>(e.source().begin.line), "TOML syntax error: " + printable_cell(e.description()));
  }
  for (const auto& [key, node] : root) {
    if (key.str() != "fact") {
      fail(source_name, static_cast<int>(node.source().begin.line),
           "unknown table or key '" + printable_cell(key.str()) + "' (a facts file holds [[fact]] tables)");
    }
  }
  const toml::array* array = root["fact"].as_array();
  if (array == nullptr || array->empty()) fail(source_name, 0, "no [[fact]] table");
  std::vector<Fact> facts;
  for (const toml::node& node : *array) {
    const int line = static_cast<int>(node.source().begin.line);
    const toml::table* table = node.as_table();
    if (table == nullptr) fail(source_name, line, "fact: expected a table ([[fact]])");
    FactReader r(source_name, *table, line);
    Fact f;
    f.line = line;
    const std::optional<std::string> kind = r.text("kind");
    if (!kind) fail(source_name, line, "fact needs kind (peak_frequency, dead_zone_onset, saturation_ratio, speed)");
    std::vector<std::string_view> allowed{"id", "kind", "target", "min", "max", "tolerance"};
    const std::map<std::string_view, std::vector<std::string_view>> kind_keys{
        {"peak_frequency", {"paper_v", "load_n", "search_hz"}},
        {"dead_zone_onset", {"frequency_hz", "load_n", "threshold_mm_s", "search_paper_v"}},
        {"saturation_ratio", {"frequency_hz", "paper_v"}},
        {"speed", {"paper_v", "frequency_hz", "load_n"}}};
    for (const char* retired : {"vpp", "search_vpp"}) {
      if (table->contains(retired)) {
        fail(source_name, line,
             std::string(retired) + ": retired key; give the voltage as the source quotes it as " +
                 (retired[0] == 's' ? "search_paper_v" : "paper_v") + " (read through options.paper_voltage_axis)");
      }
    }
    if (const auto it = kind_keys.find(*kind); it != kind_keys.end()) {
      allowed.insert(allowed.end(), it->second.begin(), it->second.end());
      r.check_known(allowed);
    }
    if (*kind == "peak_frequency") {
      f.kind = FactKind::peak_frequency;
      f.paper_v = r.required("paper_v", *kind);
      f.load_n = r.number("load_n").value_or(0.0);
      r.numbers("search_hz", f.search_hz);
      if (!(f.search_hz[0] < f.search_hz[1] && f.search_hz[2] > 0.0 &&
            f.search_hz[2] <= f.search_hz[1] - f.search_hz[0])) {
        fail(source_name, line,
             "search_hz: expected [start, stop, step] with start < stop and 0 < step <= stop - start");
      }
      // Each grid point is a run to steady state, at every evaluation of the fit.
      if ((f.search_hz[1] - f.search_hz[0]) / f.search_hz[2] > kMaxSearchPoints) {
        fail(source_name, line, "search_hz: more than " + std::to_string(kMaxSearchPoints) + " grid points");
      }
      r.range("search_hz", f.search_hz[0], 1000.0, 200000.0);
      r.range("search_hz", f.search_hz[1], 1000.0, 200000.0);
    } else if (*kind == "dead_zone_onset") {
      f.kind = FactKind::dead_zone_onset;
      f.frequency_hz = r.required("frequency_hz", *kind);
      f.load_n = r.number("load_n").value_or(0.0);
      f.threshold_mm_s = r.number("threshold_mm_s").value_or(f.threshold_mm_s);
      r.numbers("search_paper_v", f.search_paper_v);
      if (!(f.threshold_mm_s > 0.0 && f.threshold_mm_s <= 1e4)) {
        fail(source_name, line, "threshold_mm_s: must be in (0, 10000]");
      }
      if (!(f.search_paper_v[0] >= 1.0 && f.search_paper_v[1] > f.search_paper_v[0] + 10.0 &&
            f.search_paper_v[1] <= 10000.0)) {
        fail(source_name, line, "search_paper_v: expected [low, high] with 1 <= low, low + 10 < high <= 10000");
      }
    } else if (*kind == "saturation_ratio") {
      f.kind = FactKind::saturation_ratio;
      f.frequency_hz = r.required("frequency_hz", *kind);
      r.numbers("paper_v", f.ratio_paper_v);
      for (std::size_t k = 0; k < 4; ++k) {
        r.range("paper_v", f.ratio_paper_v[k], 1.0, 10000.0);
        if (k > 0 && !(f.ratio_paper_v[k] > f.ratio_paper_v[k - 1])) {
          fail(source_name, line, "paper_v: the four voltages must increase");
        }
      }
    } else if (*kind == "speed") {
      f.kind = FactKind::speed;
      f.paper_v = r.required("paper_v", *kind);
      f.frequency_hz = r.required("frequency_hz", *kind);
      f.load_n = r.number("load_n").value_or(0.0);
    } else {
      fail(source_name, line,
           "unknown kind '" + printable_cell(*kind) +
               "' (known: peak_frequency, dead_zone_onset, saturation_ratio, speed)");
    }
    if (f.kind == FactKind::peak_frequency || f.kind == FactKind::speed) r.range("paper_v", f.paper_v, 1.0, 10000.0);
    if (f.kind != FactKind::peak_frequency) r.range("frequency_hz", f.frequency_hz, 1000.0, 200000.0);
    r.range("load_n", f.load_n, -1000.0, 1000.0);
    f.target = r.number("target");
    const std::optional<double> lo = r.number("min"), hi = r.number("max");
    const std::optional<double> tolerance = r.number("tolerance");
    if (!tolerance || !(*tolerance > 0.0)) fail(source_name, line, "tolerance: required, and must be > 0");
    f.tolerance = *tolerance;
    if (f.target && (lo || hi)) fail(source_name, line, "give either target or min/max, not both");
    if (!f.target && !lo && !hi) fail(source_name, line, "fact needs a target, or min and/or max");
    f.min = f.target ? *f.target - f.tolerance : lo.value_or(-kInfinity);
    f.max = f.target ? *f.target + f.tolerance : hi.value_or(kInfinity);
    if (!(f.min <= f.max)) fail(source_name, line, "min > max");
    if (!(std::isfinite(f.min) || f.min == -kInfinity) || !(std::isfinite(f.max) || f.max == kInfinity) ||
        (f.target && !(std::isfinite(f.min) && std::isfinite(f.max)))) {
      fail(source_name, line, "target +- tolerance overflows");
    }
    const std::optional<std::string> id = r.text("id");
    f.id = id ? *id : std::string(fact_kind_name(f.kind)) + " (line " + std::to_string(line) + ")";
    facts.push_back(f);
  }
  return facts;
}

}  // namespace swum
