#include "http/http_json.h"

#include "core/cia402_state.h"
#include "nmt.h"

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace swum::emu {
namespace {

using nlohmann::json;

// nlohmann's messages start with "[json.exception.parse_error.101] ": the reader wants the rest.
std::string parse_message(const json::exception& e) {
  std::string text = e.what();
  if (const auto end = text.find("] "); text.rfind("[json.exception", 0) == 0 && end != std::string::npos)
    text.erase(0, end + 2);
  return text;
}

// A JSON object, refusing what nlohmann would accept silently: a key given twice in one object
// (the last would win; a scenario file refuses it as "key K given twice").
json parse_object(std::string_view body) {
  std::vector<std::vector<std::string>> keys;  // per open object
  const json::parser_callback_t refuse_duplicates = [&keys](int, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::object_start) keys.emplace_back();
    if (event == json::parse_event_t::object_end && !keys.empty()) keys.pop_back();
    if (event == json::parse_event_t::key && !keys.empty()) {
      const std::string& key = parsed.get_ref<const std::string&>();
      for (const std::string& seen : keys.back())
        if (seen == key) throw HttpError(400, "key " + key + " given twice");
      keys.back().push_back(key);
    }
    return true;
  };
  json value;
  try {
    value = json::parse(body.begin(), body.end(), refuse_duplicates);
  } catch (const json::exception& e) {
    throw HttpError(400, "malformed JSON: " + parse_message(e));
  }
  if (!value.is_object()) throw HttpError(400, std::string("the body must be a JSON object, not ") + value.type_name());
  return value;
}

std::string fault_names() {
  std::string list;
  for (int i = 0; i <= static_cast<int>(EventType::clear); ++i) {
    const auto type = static_cast<EventType>(i);
    if (!is_fault(type)) continue;
    list += list.empty() ? "" : ", ";
    list += to_string(type);
  }
  return list;
}

// A fault's name in a request: a fault (or `clear` where allowed), else why not.
EventType fault_type(std::string_view name, bool allow_clear, int unknown_status) {
  const auto type = event_type_from_string(name);
  if (!type)
    throw HttpError(unknown_status, "unknown fault '" + std::string(name) + "' (faults: " + fault_names() + ")");
  if (!is_fault(*type) && !(allow_clear && *type == EventType::clear))
    throw HttpError(400, std::string(to_string(*type)) + " is not a fault (the API starts faults: " + fault_names() +
                             "; load and ambient belong in a scenario)");
  return *type;
}

json electrical_json(const protocol::ElectricalValues& e) {
  return {{"current_a_a", e.current_a_a},
          {"current_b_a", e.current_b_a},
          {"phase_a_deg", e.phase_a_deg},
          {"phase_b_deg", e.phase_b_deg},
          {"motional_phase_a_deg", e.motional_phase_a_deg},
          {"motional_phase_b_deg", e.motional_phase_b_deg},
          {"power_a_w", e.power_a_w},
          {"power_b_w", e.power_b_w}};
}

// JSON has no NaN/Inf: such a value (a model blow-up caught this tick) is sent as null.
json number(double value) { return std::isfinite(value) ? json(value) : json(nullptr); }

json parameters_json(EventType type, const EventParameters& p) {
  json out = json::object();
  for (const EventKey& key : event_keys(type)) {
    if (key.kind == "phase") {
      out[key.name] = p.phase == Phase::A ? "A" : "B";
    } else if (key.kind == "fault") {
      out[key.name] = to_string(p.fault);
    } else if (key.kind == "integer") {
      out[key.name] = p.count;
    } else if (key.name == "position_um") {
      out[key.name] = p.position_um ? json(*p.position_um) : json(nullptr);
    } else {
      // The number keys of the faults: EventParameters' members of the same name.
      const std::pair<const char*, double> numbers[] = {{"duration_s", p.duration_s}, {"factor", p.factor},
                                                        {"sigma_um", p.sigma_um},     {"bias_mm_s", p.bias_mm_s},
                                                        {"sigma_mm_s", p.sigma_mm_s}, {"delay_ms", p.delay_ms}};
      for (const auto& [name, value] : numbers)
        if (key.name == name) out[key.name] = value;
    }
  }
  return out;
}

}  // namespace

json loop_json(const protocol::LoopTiming& l) {
  return {{"overruns", l.overruns},
          {"lateness_p50_ns", l.lateness_p50_ns},
          {"lateness_p99_ns", l.lateness_p99_ns},
          {"lateness_p999_ns", l.lateness_p999_ns},
          {"lateness_max_ns", l.lateness_max_ns},
          {"compute_p99_ns", l.compute_p99_ns},
          {"compute_max_ns", l.compute_max_ns}};
}

// The CiA 402 drive and its NMT state (docs/canopen.md), null when the node speaks no CANopen.
static json canopen_json(const Telemetry& t, std::uint8_t nmt_state) {
  if (nmt_state == SharedState::kNoCanopen) return nullptr;
  const auto& d = t.cia402;
  return {{"nmt", canopen::to_string(static_cast<canopen::NmtState>(nmt_state))},
          {"cia402_state", to_string(static_cast<Cia402State>(d.state))},
          {"statusword", d.statusword},
          {"error_code", d.error_code},
          {"mode_display", d.mode_display},
          {"velocity_demand_m_s", number(d.velocity_demand_m_s)},
          {"tracking_frequency_hz", number(d.tracking_frequency_hz)},
          {"terminal_amplitude_v", number(d.terminal_amplitude_v)}};
}

json state_json(const Telemetry& t, const RejectSnapshot& rejects, const ResonanceEstimate& resonance,
                std::uint8_t canopen_nmt_state) {
  const auto& s = t.setpoints;
  return {
      {"tick", t.tick},
      {"sim_time_s", t.sim_time_s},
      {"state", to_string(t.state)},
      {"fault", identifier(t.fault)},
      {"fault_code", static_cast<int>(t.fault)},
      {"enable_line", t.enable_line},
      {"at_setpoint", t.at_setpoint},
      {"drive_on", protocol::drive_on(t)},
      {"external_clock", t.external_clock},
      {"setpoints",
       {{"frequency_hz", s.frequency_hz},
        {"amplitude_v", s.amplitude_v},
        {"phase_deg", s.phase_deg},
        {"load_n", s.load_n},
        {"frequency_slew_hz_per_s", s.frequency_slew_hz_per_s},
        {"amplitude_slew_v_per_s", s.amplitude_slew_v_per_s}}},
      {"output",
       {{"amplitude_v", t.output.amplitude_v},
        {"frequency_hz", t.output.frequency_hz},
        {"phase_deg", t.output.phase_deg},
        {"load_n", t.output.load_n}}},
      {"speed_m_s", number(t.speed_m_s)},
      {"tick_speed_m_s", number(t.tick_speed_m_s)},
      {"position_m", number(t.position_m)},
      {"tip_normal_um", number(t.tip_normal_um)},
      {"tip_tangential_um", number(t.tip_tangential_um)},
      {"electrical", electrical_json(t.electrical)},
      {"stator_temperature_c", number(t.stator_temperature_c)},
      {"applied_commands", t.applied_commands},
      {"amplifier_rejects", t.amplifier_rejects},
      {"last_sequence", t.last_sequence},
      {"divergences", t.divergences},
      {"rejects", {{"last", identifier(rejects.last)}, {"count", rejects.count}}},
      {"loop", loop_json(t.stats)},
      {"resonance",
       {{"amplitude_v", resonance.amplitude_v},
        {"normal_peak_hz", number(resonance.normal_peak_hz)},
        {"tangential_peak_hz", number(resonance.tangential_peak_hz)}}},
      {"canopen", canopen_json(t, canopen_nmt_state)},
  };
}

json fault_types_json() {
  json types = json::array();
  for (int i = 0; i <= static_cast<int>(EventType::clear); ++i) {
    const auto type = static_cast<EventType>(i);
    if (!is_fault(type)) continue;
    json keys = json::array();
    for (const EventKey& key : event_keys(type)) {
      json k = {{"name", key.name}, {"kind", key.kind}, {"required", key.required}};
      if (key.kind == "number" || key.kind == "integer") {
        k["min"] = key.min;
        k["max"] = key.max;
        k["min_exclusive"] = key.min_open;
      }
      keys.push_back(std::move(k));
    }
    types.push_back({{"type", to_string(type)}, {"keys", std::move(keys)}});
  }
  return types;
}

json active_faults_json(const ActiveFaults& faults, double tick_hz) {
  json active = json::array();
  for (std::uint32_t i = 0; i < faults.count && i < faults.items.size(); ++i) {
    const ActiveFault& f = faults.items[i];
    active.push_back(
        {{"type", to_string(f.type)},
         {"since_s", static_cast<double>(f.since_tick) / tick_hz},
         {"until_s", f.until_tick == 0 ? json(nullptr) : json(static_cast<double>(f.until_tick) / tick_hz)},
         {"parameters", parameters_json(f.type, f.parameters)}});
  }
  return active;
}

RuntimeEvent parse_fault_request(std::string_view body) {
  const json request = parse_object(body);
  const auto type_it = request.find("type");
  if (type_it == request.end() || !type_it->is_string())
    throw HttpError(400, "the body needs \"type\": a fault's name (faults: " + fault_names() + ")");
  const EventType type = fault_type(type_it->get<std::string>(), true, 400);
  std::vector<std::pair<std::string, EventValue>> values;
  for (const auto& [key, value] : request.items()) {
    if (key == "type") continue;
    EventValue v;
    if (value.is_number_integer() && !value.is_number_unsigned()) {
      v.kind = EventValue::Kind::integer;
      v.integer = value.get<std::int64_t>();
    } else if (value.is_number_unsigned() &&
               value.get<std::uint64_t>() <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
      v.kind = EventValue::Kind::integer;
      v.integer = static_cast<std::int64_t>(value.get<std::uint64_t>());
    } else if (value.is_number()) {
      v.kind = EventValue::Kind::floating;
      v.floating = value.get<double>();
    } else if (value.is_string()) {
      v.kind = EventValue::Kind::name;
      v.name = value.get<std::string>();
    } else {
      throw HttpError(400, std::string(to_string(type)) + ": key " + key + " must be a number or a name, not " +
                               value.type_name());
    }
    values.emplace_back(key, std::move(v));
  }
  try {
    const ScenarioEvent event = make_event(type, values, 0.0, "http");
    return {event.type, event.parameters};
  } catch (const ScenarioError& e) {
    throw HttpError(400, e.what());
  }
}

RuntimeEvent clear_request(std::string_view type) {
  RuntimeEvent event;
  event.type = EventType::clear;
  event.parameters.fault = fault_type(type, false, 404);
  return event;
}

std::uint64_t parse_step_request(std::string_view body, double tick_hz, std::uint64_t max_ticks) {
  const json request = parse_object(body);
  const bool has_ticks = request.contains("ticks");
  const bool has_seconds = request.contains("seconds");
  if (has_ticks == has_seconds) throw HttpError(400, "the body needs exactly one of \"ticks\" and \"seconds\"");
  for (const auto& [key, value] : request.items())
    if (key != "ticks" && key != "seconds")
      throw HttpError(400, "unknown key " + key + " (step takes ticks or seconds)");
  double ticks = 0.0;
  if (has_ticks) {
    const json& v = request["ticks"];
    if (!v.is_number_integer()) throw HttpError(400, std::string("ticks must be a whole number, not ") + v.dump());
    ticks = v.is_number_unsigned() ? static_cast<double>(v.get<std::uint64_t>())
                                   : static_cast<double>(v.get<std::int64_t>());
  } else {
    const json& v = request["seconds"];
    if (!v.is_number()) throw HttpError(400, std::string("seconds must be a number, not ") + v.type_name());
    const double whole = std::round(v.get<double>() * tick_hz);
    if (std::abs(v.get<double>() * tick_hz - whole) > 1e-6 * std::max(1.0, whole))
      throw HttpError(400,
                      "seconds " + v.dump() + " is not a whole number of ticks at " + json(tick_hz).dump() + " Hz");
    ticks = whole;
  }
  if (!(ticks >= 1.0) || ticks > static_cast<double>(max_ticks))
    throw HttpError(400, "a step of " + json(ticks).dump() + " ticks is out of range [1, " + std::to_string(max_ticks) +
                             "]");
  return static_cast<std::uint64_t>(ticks);
}

std::string error_body(std::string_view message) {
  std::string line(message);
  for (char& c : line)
    if (c == '\n' || c == '\r') c = ' ';
  // The message may quote the request (a path, a value) in bytes that are not UTF-8: replaced
  // (U+FFFD), never a throw from the error path.
  return json{{"error", line}}.dump(-1, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace swum::emu
