#include "core/scenario.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

#include <toml++/toml.h>

#include "formats/number_format.h"

namespace swum::emu {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kMaxTime_s = 1e6;
constexpr double kMaxLoad_n = 30.0;

enum class ValueKind : std::uint8_t { number, optional_number, integer, phase, fault };

// One key of an event type: its value's kind, its allowed range and where it goes.
struct KeySpec {
  std::string_view name;
  ValueKind kind = ValueKind::number;
  double min = -kInfinity;
  double max = kInfinity;
  bool min_open = false;  // (min, max] instead of [min, max]
  bool required = true;
  double EventParameters::*number = nullptr;  // ValueKind::number
};

struct TypeSpec {
  EventType type;
  std::string_view name;
  std::vector<KeySpec> keys;
};

using P = EventParameters;

KeySpec closed(std::string_view name, double P::*member, double min, double max) {
  return {.name = name, .min = min, .max = max, .number = member};
}
KeySpec positive(std::string_view name, double P::*member, double max) {
  return {.name = name, .min = 0.0, .max = max, .min_open = true, .number = member};
}
// duration_s of the faults that last: 0 = until cleared.
KeySpec optional_duration() {
  return {.name = "duration_s", .min = 0.0, .max = kMaxTime_s, .required = false, .number = &P::duration_s};
}
KeySpec phase_key() { return {.name = "phase", .kind = ValueKind::phase}; }

// Indexed by EventType (same order).
const std::vector<TypeSpec>& type_specs() {
  static const std::vector<TypeSpec> specs = {
      {EventType::load_step, "load_step", {closed("load_n", &P::load_n, -kMaxLoad_n, kMaxLoad_n)}},
      {EventType::load_ramp,
       "load_ramp",
       {closed("to_n", &P::to_n, -kMaxLoad_n, kMaxLoad_n), positive("duration_s", &P::duration_s, kMaxTime_s)}},
      {EventType::load_sine,
       "load_sine",
       {closed("offset_n", &P::offset_n, -kMaxLoad_n, kMaxLoad_n),
        closed("amplitude_n", &P::amplitude_n, -kMaxLoad_n, kMaxLoad_n),
        positive("frequency_hz", &P::frequency_hz, 1000.0), optional_duration()}},
      {EventType::ambient, "ambient", {closed("temperature_c", &P::temperature_c, -40.0, 150.0)}},
      {EventType::phase_open, "phase_open", {phase_key(), optional_duration()}},
      {EventType::phase_short, "phase_short", {phase_key()}},
      {EventType::over_temperature, "over_temperature", {}},
      {EventType::voltage_sag, "voltage_sag", {closed("factor", &P::factor, 0.0, 1.0), optional_duration()}},
      {EventType::jam,
       "jam",
       {{.name = "position_um", .kind = ValueKind::optional_number, .min = -1e6, .max = 1e6, .required = false},
        optional_duration()}},
      {EventType::guide_friction, "guide_friction", {closed("factor", &P::factor, 0.0, 10.0), optional_duration()}},
      {EventType::preload_loss, "preload_loss", {closed("factor", &P::factor, 0.0, 1.0), optional_duration()}},
      {EventType::encoder_stuck, "encoder_stuck", {optional_duration()}},
      {EventType::encoder_noise, "encoder_noise", {positive("sigma_um", &P::sigma_um, 1e4), optional_duration()}},
      {EventType::speed_frozen, "speed_frozen", {optional_duration()}},
      {EventType::speed_bias, "speed_bias", {closed("bias_mm_s", &P::bias_mm_s, -1000.0, 1000.0), optional_duration()}},
      {EventType::speed_noise, "speed_noise", {positive("sigma_mm_s", &P::sigma_mm_s, 1000.0), optional_duration()}},
      {EventType::telemetry_silence, "telemetry_silence", {positive("duration_s", &P::duration_s, kMaxTime_s)}},
      {EventType::modbus_drop,
       "modbus_drop",
       {{.name = "count", .kind = ValueKind::integer, .min = 1.0, .max = 1e6, .required = false}}},
      {EventType::modbus_delay, "modbus_delay", {positive("delay_ms", &P::delay_ms, 10000.0), optional_duration()}},
      {EventType::can_bus_off, "can_bus_off", {positive("duration_s", &P::duration_s, kMaxTime_s)}},
      {EventType::clear, "clear", {{.name = "fault", .kind = ValueKind::fault}}},
  };
  return specs;
}

const TypeSpec& spec_of(EventType type) { return type_specs().at(static_cast<std::size_t>(type)); }

const KeySpec kAtSpec{.name = "at_s", .min = 0.0, .max = kMaxTime_s};

// The one shortest-decimal writer (formats/number_format.h), its exponent written as in the
// scenario files: without '+' and leading zeros ("1e6", "2.5e-7").
std::string scenario_number(double value) {
  std::string text = shortest_decimal(value);
  const auto e = text.find('e');
  if (e != std::string::npos) {
    std::size_t digits = e + 1;
    if (digits < text.size() && text[digits] == '+') text.erase(digits, 1);
    if (digits < text.size() && text[digits] == '-') ++digits;
    while (digits + 1 < text.size() && text[digits] == '0') text.erase(digits, 1);
  }
  return text;
}

std::string join_names(bool faults_only) {
  std::string list;
  for (const auto& spec : type_specs()) {
    if (faults_only && !is_fault(spec.type)) continue;
    list += list.empty() ? "" : ", ";
    list += spec.name;
  }
  return list;
}

std::string range_text(const KeySpec& key) {
  return (key.min_open ? "(" : "[") + scenario_number(key.min) + ", " + scenario_number(key.max) + "]";
}

// One key's value as written, from a TOML node or from --inject text.
struct RawValue {
  enum class Kind : std::uint8_t { integer, floating, string, other } kind = Kind::other;
  std::int64_t integer = 0;
  double floating = 0.0;
  std::string text;  // the string; for `other` what it is ("a boolean")

  [[nodiscard]] bool is_number() const { return kind == Kind::integer || kind == Kind::floating; }
  [[nodiscard]] double number() const { return kind == Kind::integer ? static_cast<double>(integer) : floating; }
  // For "must be X, not ...".
  [[nodiscard]] std::string describe() const {
    switch (kind) {
      case Kind::integer: return std::to_string(integer);
      case Kind::floating: {
        // 1.0 shown as "1.0": "count must be an integer, not 1" would contradict itself.
        auto text = scenario_number(floating);
        if (std::isfinite(floating) && text.find_first_of(".e") == std::string::npos) text += ".0";
        return text;
      }
      case Kind::string: return "\"" + text + "\"";
      case Kind::other: break;
    }
    return text;
  }
};

RawValue raw_from_node(const toml::node& node) {
  RawValue raw;
  if (const auto* i = node.as_integer()) {
    raw.kind = RawValue::Kind::integer;
    raw.integer = i->get();
  } else if (const auto* f = node.as_floating_point()) {
    raw.kind = RawValue::Kind::floating;
    raw.floating = f->get();
  } else if (const auto* s = node.as_string()) {
    raw.kind = RawValue::Kind::string;
    raw.text = s->get();
  } else if (node.is_boolean()) {
    raw.text = "a boolean";
  } else if (node.is_table()) {
    raw.text = "a table";
  } else if (node.is_array()) {
    raw.text = "an array";
  } else {
    raw.text = "a date or time";
  }
  return raw;
}

// --inject text: a whole decimal number is an integer, a complete decimal floating-point number
// (also nan, inf) a floating one, anything else a string.
RawValue raw_from_text(std::string_view text) {
  RawValue raw;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  const std::size_t sign = (!text.empty() && text[0] == '-') ? 1 : 0;
  const bool decimal = text.size() > sign && std::all_of(text.begin() + static_cast<std::ptrdiff_t>(sign), text.end(),
                                                         [](char c) { return c >= '0' && c <= '9'; });
  if (decimal) {
    const auto [end, ec] = std::from_chars(first, last, raw.integer);
    if (ec == std::errc{} && end == last) {
      raw.kind = RawValue::Kind::integer;
      return raw;
    }
  }
  if (!text.empty()) {
    const auto [end, ec] = std::from_chars(first, last, raw.floating, std::chars_format::general);
    if (end == last && ec == std::errc{}) {
      raw.kind = RawValue::Kind::floating;
      return raw;
    }
    if (end == last && ec == std::errc::result_out_of_range) {
      // Too large (or too small) for a double: infinite (or zero) with its sign.
      const auto e = text.find_first_of("eE");
      const bool tiny = e != std::string_view::npos && e + 1 < text.size() && text[e + 1] == '-';
      raw.floating = std::copysign(tiny ? 0.0 : kInfinity, sign != 0 ? -1.0 : 1.0);
      raw.kind = RawValue::Kind::floating;
      return raw;
    }
  }
  raw.kind = RawValue::Kind::string;
  raw.text = std::string(text);
  return raw;
}

// A number key's value (finite, in range) or the problem.
std::string read_number(const KeySpec& key, const RawValue& value, double& out) {
  const std::string name(key.name);
  if (!value.is_number()) return name + " must be a number, not " + value.describe();
  const double v = value.number();
  if (!std::isfinite(v)) return name + " must be finite, not " + value.describe();
  const bool above_min = key.min_open ? v > key.min : v >= key.min;
  if (!above_min || v > key.max) return name + " " + value.describe() + " out of range " + range_text(key);
  out = v;
  return {};
}

// Sets one key of an event; returns the problem ("" when fine).
std::string apply(const KeySpec& key, const RawValue& value, EventParameters& p) {
  const std::string name(key.name);
  switch (key.kind) {
    case ValueKind::number: return read_number(key, value, p.*key.number);
    case ValueKind::optional_number: {
      double v = 0.0;
      auto problem = read_number(key, value, v);
      if (problem.empty()) p.position_um = v;
      return problem;
    }
    case ValueKind::integer: {
      if (value.kind != RawValue::Kind::integer) return name + " must be an integer, not " + value.describe();
      double v = 0.0;
      auto problem = read_number(key, value, v);
      if (problem.empty()) p.count = static_cast<std::uint32_t>(v);
      return problem;
    }
    case ValueKind::phase:
      if (value.kind == RawValue::Kind::string && (value.text == "A" || value.text == "B")) {
        p.phase = value.text == "A" ? Phase::A : Phase::B;
        return {};
      }
      return name + " must be \"A\" or \"B\", not " + value.describe();
    case ValueKind::fault: {
      const auto type = value.kind == RawValue::Kind::string ? event_type_from_string(value.text) : std::nullopt;
      if (type && is_fault(*type)) {
        p.fault = *type;
        return {};
      }
      return name + " " + value.describe() + " is not a fault (faults: " + join_names(true) + ")";
    }
  }
  return name + ": unknown kind";
}

// The keys of one event, as they come; the problems without the where and the type.
class EventBuilder {
 public:
  explicit EventBuilder(EventType type) : spec_(spec_of(type)), seen_(spec_.keys.size(), false) {}

  std::string set(std::string_view key, const RawValue& value) {
    for (std::size_t k = 0; k < spec_.keys.size(); ++k) {
      if (spec_.keys[k].name != key) continue;
      if (seen_[k]) return "key " + std::string(key) + " given twice";
      seen_[k] = true;
      return apply(spec_.keys[k], value, parameters_);
    }
    std::string known;
    for (const auto& k : spec_.keys) known += (known.empty() ? "" : ", ") + std::string(k.name);
    return "unknown key " + std::string(key) + " (" + std::string(spec_.name) +
           (known.empty() ? " takes no keys)" : " takes: " + known + ")");
  }

  // Missing keys and the checks across keys.
  std::string finish() const {
    for (std::size_t k = 0; k < spec_.keys.size(); ++k) {
      if (spec_.keys[k].required && !seen_[k]) return "missing key " + std::string(spec_.keys[k].name);
    }
    if (spec_.type == EventType::load_sine) {
      const double peak_n = std::abs(parameters_.offset_n) + std::abs(parameters_.amplitude_n);
      if (peak_n > kMaxLoad_n) {
        return "|offset_n| + |amplitude_n| = " + scenario_number(peak_n) + " exceeds " + scenario_number(kMaxLoad_n);
      }
    }
    return {};
  }

  [[nodiscard]] const EventParameters& parameters() const { return parameters_; }

 private:
  const TypeSpec& spec_;
  std::vector<bool> seen_;
  EventParameters parameters_;
};

std::string where(const std::string& file_name, const toml::source_region& region) {
  std::string s = file_name;
  if (region.begin.line > 0) s += ":" + std::to_string(region.begin.line);
  return s;
}

std::string unknown_type(std::string_view name) {
  return "unknown event type \"" + std::string(name) + "\" (known: " + join_names(false) + ")";
}

ScenarioEvent read_event(const toml::table& table, const std::string& file_name) {
  ScenarioEvent event;
  event.origin = where(file_name, table.source());
  const toml::node* type_node = table.get("type");
  if (type_node == nullptr)
    throw ScenarioError(event.origin + ": event without type (known: " + join_names(false) + ")");
  const auto* type_name = type_node->as_string();
  if (type_name == nullptr) {
    throw ScenarioError(where(file_name, type_node->source()) + ": event type must be a string, not " +
                        raw_from_node(*type_node).describe());
  }
  const auto type = event_type_from_string(type_name->get());
  if (!type) throw ScenarioError(where(file_name, type_node->source()) + ": " + unknown_type(type_name->get()));
  event.type = *type;
  const std::string prefix = std::string(": ") + to_string(*type) + ": ";
  const toml::node* at_node = table.get("at_s");
  if (at_node == nullptr) throw ScenarioError(event.origin + prefix + "missing key at_s");
  if (auto problem = read_number(kAtSpec, raw_from_node(*at_node), event.at_s); !problem.empty()) {
    throw ScenarioError(where(file_name, at_node->source()) + prefix + problem);
  }
  EventBuilder builder(*type);
  for (auto&& [key, node] : table) {
    if (key.str() == "type" || key.str() == "at_s") continue;
    if (auto problem = builder.set(key.str(), raw_from_node(node)); !problem.empty()) {
      throw ScenarioError(where(file_name, node.source()) + prefix + problem);
    }
  }
  if (auto problem = builder.finish(); !problem.empty()) throw ScenarioError(event.origin + prefix + problem);
  event.parameters = builder.parameters();
  return event;
}

std::string one_line(const std::string& message) {
  std::string out;
  char hex[5];
  for (const char c : message) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7F) {
      std::snprintf(hex, sizeof hex, "\\x%02X", byte);
      out += hex;
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace

const char* to_string(EventType type) {
  const auto index = static_cast<std::size_t>(type);
  return index < type_specs().size() ? type_specs()[index].name.data() : "unknown";
}

std::optional<EventType> event_type_from_string(std::string_view name) {
  for (const auto& spec : type_specs()) {
    if (spec.name == name) return spec.type;
  }
  return std::nullopt;
}

bool is_fault(EventType type) { return type >= EventType::phase_open && type <= EventType::can_bus_off; }

ScenarioError::ScenarioError(const std::string& message) : std::runtime_error(one_line(message)) {}

Scenario parse_scenario(std::string_view toml_text, const std::string& file_name) {
  toml::table root;
  try {
    root = toml::parse(toml_text, std::string_view(file_name));
  } catch (const toml::parse_error& e) {
    throw ScenarioError(where(file_name, e.source()) + ": TOML syntax error: " + std::string(e.description()));
  }
  Scenario scenario;
  for (auto&& [key, node] : root) {
    const std::string here = where(file_name, node.source());
    if (key.str() == "name") {
      const auto* name = node.as_string();
      if (name == nullptr) throw ScenarioError(here + ": name must be a string, not " + raw_from_node(node).describe());
      scenario.name = name->get();
    } else if (key.str() == "seed") {
      const auto* seed = node.as_integer();
      if (seed == nullptr || seed->get() < 0) {
        throw ScenarioError(here + ": seed must be an integer >= 0, not " + raw_from_node(node).describe());
      }
      scenario.seed = static_cast<std::uint64_t>(seed->get());
    } else if (key.str() == "event") {
      const auto* events = node.as_array();
      if (events == nullptr) {
        throw ScenarioError(here + ": event must be an array of tables ([[event]]), not " +
                            raw_from_node(node).describe());
      }
      for (const auto& element : *events) {
        const auto* table = element.as_table();
        if (table == nullptr) {
          throw ScenarioError(where(file_name, element.source()) + ": event must be a table ([[event]]), not " +
                              raw_from_node(element).describe());
        }
        scenario.events.push_back(read_event(*table, file_name));
      }
    } else {
      throw ScenarioError(here + ": unknown top-level key " + std::string(key.str()) + " (known: name, seed, event)");
    }
  }
  std::stable_sort(scenario.events.begin(), scenario.events.end(),
                   [](const ScenarioEvent& a, const ScenarioEvent& b) { return a.at_s < b.at_s; });
  return scenario;
}

ScenarioEvent parse_injection(std::string_view text) {
  const std::string here = "--inject '" + std::string(text) + "': ";
  const auto at = text.find('@');
  if (at == std::string_view::npos) throw ScenarioError(here + "expected NAME@SECONDS[:key=value,...]");
  const auto type = event_type_from_string(text.substr(0, at));
  if (!type) throw ScenarioError(here + unknown_type(text.substr(0, at)));
  ScenarioEvent event;
  event.type = *type;
  event.origin = "--inject";
  const std::string prefix = here + to_string(*type) + ": ";
  const std::string_view rest = text.substr(at + 1);
  const auto colon = rest.find(':');
  if (auto problem = read_number(kAtSpec, raw_from_text(rest.substr(0, colon)), event.at_s); !problem.empty()) {
    throw ScenarioError(prefix + problem);
  }
  EventBuilder builder(*type);
  if (colon != std::string_view::npos) {
    std::string_view pairs = rest.substr(colon + 1);
    while (true) {
      const auto comma = pairs.find(',');
      const std::string_view pair = pairs.substr(0, comma);
      const auto equals = pair.find('=');
      if (equals == std::string_view::npos || equals == 0) {
        throw ScenarioError(prefix + "expected key=value, not \"" + std::string(pair) + "\"");
      }
      if (auto problem = builder.set(pair.substr(0, equals), raw_from_text(pair.substr(equals + 1)));
          !problem.empty()) {
        throw ScenarioError(prefix + problem);
      }
      if (comma == std::string_view::npos) break;
      pairs.remove_prefix(comma + 1);
    }
  }
  if (auto problem = builder.finish(); !problem.empty()) throw ScenarioError(prefix + problem);
  event.parameters = builder.parameters();
  return event;
}

std::vector<EventKey> event_keys(EventType type) {
  std::vector<EventKey> keys;
  for (const KeySpec& k : spec_of(type).keys) {
    EventKey key;
    key.name = std::string(k.name);
    key.min = k.min;
    key.max = k.max;
    key.min_open = k.min_open;
    key.required = k.required;
    switch (k.kind) {
      case ValueKind::number:
      case ValueKind::optional_number: key.kind = "number"; break;
      case ValueKind::integer: key.kind = "integer"; break;
      case ValueKind::phase: key.kind = "phase"; break;
      case ValueKind::fault: key.kind = "fault"; break;
    }
    keys.push_back(std::move(key));
  }
  return keys;
}

ScenarioEvent make_event(EventType type, const std::vector<std::pair<std::string, EventValue>>& values, double at_s,
                         const std::string& origin) {
  const std::string prefix = std::string(to_string(type)) + ": ";
  ScenarioEvent event;
  event.type = type;
  event.origin = origin;
  RawValue at;
  at.kind = RawValue::Kind::floating;
  at.floating = at_s;
  if (auto problem = read_number(kAtSpec, at, event.at_s); !problem.empty()) throw ScenarioError(prefix + problem);
  EventBuilder builder(type);
  for (const auto& [key, value] : values) {
    RawValue raw;
    switch (value.kind) {
      case EventValue::Kind::integer:
        raw.kind = RawValue::Kind::integer;
        raw.integer = value.integer;
        break;
      case EventValue::Kind::floating:
        raw.kind = RawValue::Kind::floating;
        raw.floating = value.floating;
        break;
      case EventValue::Kind::name:
        raw.kind = RawValue::Kind::string;
        raw.text = value.name;
        break;
    }
    if (auto problem = builder.set(key, raw); !problem.empty()) throw ScenarioError(prefix + problem);
  }
  if (auto problem = builder.finish(); !problem.empty()) throw ScenarioError(prefix + problem);
  event.parameters = builder.parameters();
  return event;
}

std::string format_event(const ScenarioEvent& event) {
  std::string text = std::string(to_string(event.type)) + "@" + scenario_number(event.at_s);
  const EventParameters& p = event.parameters;
  char separator = ':';
  for (const auto& key : spec_of(event.type).keys) {
    std::string value;
    switch (key.kind) {
      case ValueKind::number: value = scenario_number(p.*key.number); break;
      case ValueKind::optional_number:
        if (!p.position_um) continue;
        value = scenario_number(*p.position_um);
        break;
      case ValueKind::integer: value = std::to_string(p.count); break;
      case ValueKind::phase: value = p.phase == Phase::A ? "A" : "B"; break;
      case ValueKind::fault: value = to_string(p.fault); break;
    }
    text.append(1, separator).append(key.name).append("=").append(value);
    separator = ',';
  }
  return text;
}

}  // namespace swum::emu
