// firmware_sim/http/http_json.h: the HTTP API's JSON without sockets. The telemetry snapshot (every
// key, NaN as null, the fault code as its number), the fault types and the faults in force, the
// fault request (each refusal with its status and the scenario file's message), the DELETE
// clear, the step request and the one-line error body.
#include "http/http_json.h"

#include "core/cia402_state.h"
#include "nmt.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <string_view>

namespace swum::emu {
namespace {

using nlohmann::json;

// What `call` throws: {status, message}; status 0 when it returns.
struct Refusal {
  int status = 0;
  std::string message;
};
template <typename Call>
Refusal refusal(Call call) {
  try {
    (void)call();
  } catch (const HttpError& e) {
    return {e.status(), e.what()};
  }
  return {};
}
Refusal fault_refusal(std::string_view body) {
  return refusal([&] { return parse_fault_request(body); });
}
Refusal step_refusal(std::string_view body, double tick_hz = 10000.0, std::uint64_t max_ticks = 600000) {
  return refusal([&] { return parse_step_request(body, tick_hz, max_ticks); });
}
bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

constexpr auto kFaults =
    "phase_open, phase_short, over_temperature, voltage_sag, jam, guide_friction, preload_loss, encoder_stuck, "
    "encoder_noise, speed_frozen, speed_bias, speed_noise, telemetry_silence, modbus_drop, modbus_delay, "
    "can_bus_off";

// --- state_json ---------------------------------------------------------------------------------

Telemetry sample_telemetry() {
  Telemetry t;
  t.tick = 1234;
  t.sim_time_s = 0.1234;
  t.state = AmpState::fault;
  t.fault = FaultCode::over_temperature;
  t.setpoints.frequency_hz = 40000.0;
  t.setpoints.amplitude_v = 400.0;
  t.output.amplitude_v = 0.0;
  t.speed_m_s = 0.61;
  t.position_m = 0.0123;
  t.electrical.current_b_a = 0.25;
  t.stator_temperature_c = 21.5;
  t.stats.lateness_p99_ns = 4200;
  return t;
}

TEST(HttpJson, StateHasEveryTopLevelKeyAndTheNestedOnes) {
  const json j = state_json(sample_telemetry(), RejectSnapshot{Reason::fault_active, 3}, {400.0, 41000.0, 39000.0});
  const std::set<std::string> expected = {"tick",
                                          "sim_time_s",
                                          "state",
                                          "fault",
                                          "fault_code",
                                          "enable_line",
                                          "at_setpoint",
                                          "drive_on",
                                          "external_clock",
                                          "setpoints",
                                          "output",
                                          "speed_m_s",
                                          "tick_speed_m_s",
                                          "position_m",
                                          "tip_normal_um",
                                          "tip_tangential_um",
                                          "electrical",
                                          "stator_temperature_c",
                                          "applied_commands",
                                          "amplifier_rejects",
                                          "last_sequence",
                                          "divergences",
                                          "rejects",
                                          "loop",
                                          "resonance",
                                          "canopen"};
  std::set<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.insert(key);
  EXPECT_EQ(keys, expected);
  for (const char* key :
       {"frequency_hz", "amplitude_v", "phase_deg", "load_n", "frequency_slew_hz_per_s", "amplitude_slew_v_per_s"})
    EXPECT_TRUE(j["setpoints"].contains(key)) << key;
  for (const char* key : {"amplitude_v", "frequency_hz", "phase_deg", "load_n"})
    EXPECT_TRUE(j["output"].contains(key)) << key;
  for (const char* key : {"current_a_a", "current_b_a", "phase_a_deg", "phase_b_deg", "motional_phase_a_deg",
                          "motional_phase_b_deg", "power_a_w", "power_b_w"})
    EXPECT_TRUE(j["electrical"].contains(key)) << key;
  for (const char* key : {"overruns", "lateness_p50_ns", "lateness_p99_ns", "lateness_p999_ns", "lateness_max_ns",
                          "compute_p99_ns", "compute_max_ns"})
    EXPECT_TRUE(j["loop"].contains(key)) << key;
  EXPECT_EQ(j["resonance"],
            (json{{"amplitude_v", 400.0}, {"normal_peak_hz", 41000.0}, {"tangential_peak_hz", 39000.0}}));
  EXPECT_EQ(j["rejects"]["count"], 3);
  EXPECT_EQ(j["rejects"]["last"], "fault_active");
}

TEST(HttpJson, StateCarriesTheValuesInSiUnits) {
  const json j = state_json(sample_telemetry(), {}, {});
  EXPECT_EQ(j["tick"], 1234);
  EXPECT_DOUBLE_EQ(j["sim_time_s"].get<double>(), 0.1234);
  EXPECT_DOUBLE_EQ(j["speed_m_s"].get<double>(), 0.61);
  EXPECT_DOUBLE_EQ(j["position_m"].get<double>(), 0.0123);
  EXPECT_DOUBLE_EQ(j["setpoints"]["frequency_hz"].get<double>(), 40000.0);
  EXPECT_DOUBLE_EQ(j["electrical"]["current_b_a"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(j["stator_temperature_c"].get<double>(), 21.5);
  EXPECT_EQ(j["loop"]["lateness_p99_ns"], 4200);
  EXPECT_EQ(j["state"], to_string(AmpState::fault));
  EXPECT_FALSE(j["drive_on"].get<bool>());  // in fault, 0 V
}

// The CANopen node's NMT state and CiA 402 drive (docs/canopen.md): null without CANopen.
TEST(HttpJson, StateCarriesTheCanopenNodeWhenThereIsOne) {
  Telemetry t = sample_telemetry();
  EXPECT_TRUE(state_json(t, {}, {})["canopen"].is_null());
  t.cia402.active = true;
  t.cia402.state = static_cast<std::uint8_t>(Cia402State::fault);
  t.cia402.statusword = 0x0208;
  t.cia402.error_code = 0x4310;
  t.cia402.mode_display = 3;
  const json j = state_json(t, {}, {}, static_cast<std::uint8_t>(canopen::NmtState::operational));
  EXPECT_EQ(j["canopen"]["nmt"], "operational");
  EXPECT_EQ(j["canopen"]["cia402_state"], to_string(Cia402State::fault));
  EXPECT_EQ(j["canopen"]["statusword"], 0x0208);
  EXPECT_EQ(j["canopen"]["error_code"], 0x4310);
  EXPECT_EQ(j["canopen"]["mode_display"], 3);
  EXPECT_EQ(state_json(t, {}, {}, static_cast<std::uint8_t>(canopen::NmtState::pre_operational))["canopen"]["nmt"],
            "pre-operational");
}

TEST(HttpJson, StateFaultCodeIsTheWireNumberBesideTheName) {
  const json j = state_json(sample_telemetry(), {}, {});
  ASSERT_TRUE(j["fault_code"].is_number_integer());
  EXPECT_EQ(j["fault_code"].get<int>(), 4);   // protocol/codes.h: over_temperature = 4
  EXPECT_EQ(j["fault"], "over_temperature");  // the identifier, as the fault type names it
  Telemetry none = sample_telemetry();
  none.fault = FaultCode::none;
  EXPECT_EQ(state_json(none, {}, {})["fault_code"].get<int>(), 0);
}

TEST(HttpJson, StateSendsNonFiniteModelValuesAsNull) {
  Telemetry t = sample_telemetry();
  t.speed_m_s = std::numeric_limits<double>::quiet_NaN();
  t.tick_speed_m_s = std::numeric_limits<double>::infinity();
  t.position_m = -std::numeric_limits<double>::infinity();
  t.stator_temperature_c = std::numeric_limits<double>::quiet_NaN();
  const json j = state_json(t, {}, {1.0, std::numeric_limits<double>::quiet_NaN(), 39000.0});
  EXPECT_TRUE(j["speed_m_s"].is_null());
  EXPECT_TRUE(j["tick_speed_m_s"].is_null());
  EXPECT_TRUE(j["position_m"].is_null());
  EXPECT_TRUE(j["stator_temperature_c"].is_null());
  EXPECT_TRUE(j["resonance"]["normal_peak_hz"].is_null());
  EXPECT_EQ(j["resonance"]["tangential_peak_hz"], 39000.0);
  // The text is valid JSON that reads back with the nulls.
  const json back = json::parse(j.dump());
  EXPECT_TRUE(back["speed_m_s"].is_null());
}

// --- fault_types_json, active_faults_json ---------------------------------------------------------

TEST(HttpJson, FaultTypesAreExactlyTheScenarioFaultsWithTheirKeys) {
  const json types = fault_types_json();
  ASSERT_TRUE(types.is_array());
  std::string names;
  for (const json& t : types) names += (names.empty() ? "" : ", ") + t["type"].get<std::string>();
  EXPECT_EQ(names, kFaults);
  for (const json& t : types) {
    const auto type = event_type_from_string(t["type"].get<std::string>());
    ASSERT_TRUE(type.has_value());
    EXPECT_EQ(t["keys"].size(), event_keys(*type).size()) << t["type"];
  }
}

TEST(HttpJson, FaultTypesGiveNumberRangesAndNoRangeForNames) {
  const json types = fault_types_json();
  const auto of = [&](std::string_view name) {
    for (const json& t : types)
      if (t["type"] == name) return t["keys"];
    ADD_FAILURE() << name;
    return json::array();
  };
  const json sag = of("voltage_sag");
  ASSERT_EQ(sag.size(), 2U);
  EXPECT_EQ(sag[0], (json{{"name", "factor"},
                          {"kind", "number"},
                          {"required", true},
                          {"min", 0.0},
                          {"max", 1.0},
                          {"min_exclusive", false}}));
  EXPECT_EQ(sag[1]["name"], "duration_s");
  EXPECT_EQ(sag[1]["required"], false);
  EXPECT_EQ(sag[1]["max"], 1e6);
  const json noise = of("encoder_noise");
  EXPECT_EQ(noise[0]["min_exclusive"], true);  // sigma_um in (0, 1e4]
  const json drop = of("modbus_drop");
  EXPECT_EQ(drop[0], (json{{"name", "count"},
                           {"kind", "integer"},
                           {"required", false},
                           {"min", 1.0},
                           {"max", 1e6},
                           {"min_exclusive", false}}));
  const json open = of("phase_open");
  EXPECT_EQ(open[0], (json{{"name", "phase"}, {"kind", "phase"}, {"required", true}}));  // no min/max
  EXPECT_TRUE(of("over_temperature").empty());
  // Every range is finite: the text is valid JSON (an infinite bound would be written as null).
  for (const json& t : types)
    for (const json& k : t["keys"])
      if (k.contains("min")) {
        EXPECT_TRUE(k["min"].is_number()) << t["type"];
        EXPECT_TRUE(k["max"].is_number()) << t["type"];
      }
}

TEST(HttpJson, ActiveFaultsGiveTimesInSecondsAndTheParameters) {
  ActiveFaults faults;
  faults.count = 3;
  faults.items[0].type = EventType::phase_open;
  faults.items[0].since_tick = 2500;
  faults.items[0].until_tick = 3500;
  faults.items[0].parameters.phase = Phase::B;
  faults.items[0].parameters.duration_s = 0.1;
  faults.items[1].type = EventType::jam;
  faults.items[1].since_tick = 10000;
  faults.items[2].type = EventType::modbus_delay;
  faults.items[2].parameters.delay_ms = 25.0;
  faults.items[3].type = EventType::speed_frozen;  // beyond count: not listed
  const json active = active_faults_json(faults, 10000.0);
  ASSERT_EQ(active.size(), 3U);
  EXPECT_EQ(active[0]["type"], "phase_open");
  EXPECT_DOUBLE_EQ(active[0]["since_s"].get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(active[0]["until_s"].get<double>(), 0.35);
  EXPECT_EQ(active[0]["parameters"]["phase"], "B");
  EXPECT_DOUBLE_EQ(active[0]["parameters"]["duration_s"].get<double>(), 0.1);
  EXPECT_TRUE(active[1]["until_s"].is_null());                    // until cleared
  EXPECT_TRUE(active[1]["parameters"]["position_um"].is_null());  // where the mover was
  EXPECT_DOUBLE_EQ(active[1]["since_s"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(active[2]["parameters"]["delay_ms"].get<double>(), 25.0);
}

TEST(HttpJson, ActiveFaultsListNothingWhenNoneHold) {
  EXPECT_EQ(active_faults_json(ActiveFaults{}, 10000.0), json::array());
}

// --- parse_fault_request --------------------------------------------------------------------------

TEST(HttpJson, FaultRequestWithMalformedJsonIs400) {
  for (const char* body : {"", "{", "{\"type\": }", "phase_open", "{\"type\": \"jam\"} x"}) {
    const Refusal r = fault_refusal(body);
    EXPECT_EQ(r.status, 400) << body;
    EXPECT_EQ(r.message.rfind("malformed JSON: ", 0), 0U) << r.message;
    EXPECT_FALSE(contains(r.message, "[json.exception")) << r.message;  // nlohmann's prefix removed
  }
}

TEST(HttpJson, FaultRequestThatIsNotAnObjectIs400) {
  const Refusal array = fault_refusal("[{\"type\": \"jam\"}]");
  EXPECT_EQ(array.status, 400);
  EXPECT_EQ(array.message, "the body must be a JSON object, not array");
  EXPECT_EQ(fault_refusal("\"jam\"").status, 400);
  EXPECT_EQ(fault_refusal("null").status, 400);
}

TEST(HttpJson, FaultRequestWithoutAStringTypeIs400ListingTheFaults) {
  for (const char* body : {"{}", "{\"phase\": \"B\"}", "{\"type\": 3}", "{\"type\": null}"}) {
    const Refusal r = fault_refusal(body);
    EXPECT_EQ(r.status, 400) << body;
    EXPECT_EQ(r.message, std::string("the body needs \"type\": a fault's name (faults: ") + kFaults + ")") << body;
  }
}

TEST(HttpJson, FaultRequestOfAnUnknownTypeIs400ListingTheFaults) {
  const Refusal r = fault_refusal(R"({"type": "stall"})");
  EXPECT_EQ(r.status, 400);
  EXPECT_EQ(r.message, std::string("unknown fault 'stall' (faults: ") + kFaults + ")");
}

TEST(HttpJson, FaultRequestOfALoadOrAmbientEventIs400NotAFault) {
  for (const char* type : {"load_step", "load_ramp", "load_sine", "ambient"}) {
    const Refusal r = fault_refusal(std::string(R"({"type": ")") + type + R"(", "load_n": 1})");
    EXPECT_EQ(r.status, 400) << type;
    EXPECT_EQ(r.message.rfind(std::string(type) + " is not a fault (the API starts faults: ", 0), 0U) << r.message;
  }
}

TEST(HttpJson, FaultRequestWithABadValueGivesTheScenarioMessage) {
  const Refusal phase = fault_refusal(R"({"type": "phase_open", "phase": "C"})");
  EXPECT_EQ(phase.status, 400);
  EXPECT_EQ(phase.message, "phase_open: phase must be \"A\" or \"B\", not \"C\"");
  const Refusal range = fault_refusal(R"({"type": "voltage_sag", "factor": 1.5})");
  EXPECT_EQ(range.status, 400);
  EXPECT_EQ(range.message, "voltage_sag: factor 1.5 out of range [0, 1]");
  const Refusal negative = fault_refusal(R"({"type": "speed_bias", "bias_mm_s": -1001})");
  EXPECT_EQ(negative.message, "speed_bias: bias_mm_s -1001 out of range [-1000, 1000]");
  const Refusal missing = fault_refusal(R"({"type": "telemetry_silence"})");
  EXPECT_EQ(missing.status, 400);
  EXPECT_EQ(missing.message, "telemetry_silence: missing key duration_s");
  const Refusal unknown = fault_refusal(R"({"type": "jam", "duration": 2})");
  EXPECT_EQ(unknown.status, 400);
  EXPECT_EQ(unknown.message, "jam: unknown key duration (jam takes: position_um, duration_s)");
  const Refusal count = fault_refusal(R"({"type": "modbus_drop", "count": 2.5})");
  EXPECT_EQ(count.message, "modbus_drop: count must be an integer, not 2.5");
  const Refusal huge = fault_refusal(R"({"type": "modbus_drop", "count": 18446744073709551615})");
  EXPECT_EQ(huge.status, 400);  // above int64: read as a floating number, out of range
  EXPECT_TRUE(contains(huge.message, "modbus_drop: count must be an integer")) << huge.message;
}

TEST(HttpJson, FaultRequestWithABooleanOrStructuredValueIs400) {
  const Refusal boolean = fault_refusal(R"({"type": "voltage_sag", "factor": true})");
  EXPECT_EQ(boolean.status, 400);
  EXPECT_EQ(boolean.message, "voltage_sag: key factor must be a number or a name, not boolean");
  EXPECT_EQ(fault_refusal(R"({"type": "voltage_sag", "factor": null})").status, 400);
  EXPECT_EQ(fault_refusal(R"({"type": "voltage_sag", "factor": [0.5]})").status, 400);
  EXPECT_EQ(fault_refusal(R"({"type": "voltage_sag", "factor": {"v": 0.5}})").status, 400);
}

TEST(HttpJson, FaultRequestGivesTheRuntimeEventWithItsParameters) {
  const RuntimeEvent open = parse_fault_request(R"({"type": "phase_open", "phase": "B", "duration_s": 0.1})");
  EXPECT_EQ(open.type, EventType::phase_open);
  EXPECT_EQ(open.parameters.phase, Phase::B);
  EXPECT_EQ(open.parameters.duration_s, 0.1);
  const RuntimeEvent sag = parse_fault_request(R"({"type": "voltage_sag", "factor": 1})");  // an integer for a number
  EXPECT_EQ(sag.parameters.factor, 1.0);
  EXPECT_EQ(sag.parameters.duration_s, 0.0);  // default: until cleared
  const RuntimeEvent drop = parse_fault_request(R"({"type": "modbus_drop", "count": 7})");
  EXPECT_EQ(drop.parameters.count, 7U);
  EXPECT_EQ(parse_fault_request(R"({"type": "modbus_drop"})").parameters.count, 1U);
  const RuntimeEvent jam = parse_fault_request(R"({"type": "jam", "position_um": -12.5})");
  EXPECT_EQ(jam.parameters.position_um, -12.5);
  EXPECT_FALSE(parse_fault_request(R"({"type": "jam"})").parameters.position_um.has_value());
  EXPECT_EQ(parse_fault_request(R"({"type": "over_temperature"})").type, EventType::over_temperature);
}

TEST(HttpJson, FaultRequestMayClearOneFaultByItsFaultKey) {
  const RuntimeEvent clear = parse_fault_request(R"({"type": "clear", "fault": "phase_open"})");
  EXPECT_EQ(clear.type, EventType::clear);
  EXPECT_EQ(clear.parameters.fault, EventType::phase_open);
  // Not "clear everything" (that is DELETE /faults): the fault key names one fault.
  const Refusal all = fault_refusal(R"({"type": "clear", "fault": "clear"})");
  EXPECT_EQ(all.status, 400);
  EXPECT_EQ(all.message, std::string("clear: fault \"clear\" is not a fault (faults: ") + kFaults + ")");
  EXPECT_EQ(fault_refusal(R"({"type": "clear"})").message, "clear: missing key fault");
}

// --- clear_request -----------------------------------------------------------------------------

TEST(HttpJson, ClearRequestOfAFaultIsAClearOfThatFault) {
  const RuntimeEvent e = clear_request("phase_open");
  EXPECT_EQ(e.type, EventType::clear);
  EXPECT_EQ(e.parameters.fault, EventType::phase_open);
  EXPECT_EQ(clear_request("can_bus_off").parameters.fault, EventType::can_bus_off);
}

TEST(HttpJson, ClearRequestOfAnUnknownNameIs404AndOfANonFault400) {
  const Refusal unknown = refusal([] { return clear_request("nope"); });
  EXPECT_EQ(unknown.status, 404);
  EXPECT_EQ(unknown.message, std::string("unknown fault 'nope' (faults: ") + kFaults + ")");
  const Refusal load = refusal([] { return clear_request("load_step"); });
  EXPECT_EQ(load.status, 400);
  EXPECT_EQ(load.message.rfind("load_step is not a fault", 0), 0U) << load.message;
  EXPECT_EQ(refusal([] { return clear_request("clear"); }).status, 400);  // not a fault's name either
}

// --- parse_step_request ------------------------------------------------------------------------

TEST(HttpJson, StepOfTicksIsThatManyTicks) {
  EXPECT_EQ(parse_step_request(R"({"ticks": 1})", 10000.0, 600000), 1U);
  EXPECT_EQ(parse_step_request(R"({"ticks": 600000})", 10000.0, 600000), 600000U);
}

TEST(HttpJson, StepOfSecondsIsTheWholeNumberOfTicks) {
  EXPECT_EQ(parse_step_request(R"({"seconds": 0.25})", 10000.0, 600000), 2500U);
  EXPECT_EQ(parse_step_request(R"({"seconds": 0.0001})", 10000.0, 600000), 1U);
  EXPECT_EQ(parse_step_request(R"({"seconds": 1})", 10000.0, 600000), 10000U);
  EXPECT_EQ(parse_step_request(R"({"seconds": 0.0003})", 10000.0, 600000), 3U);  // 0.0003 * 1e4 = 2.9999999999999996
  EXPECT_EQ(parse_step_request(R"({"seconds": 0.07})", 10000.0, 600000), 700U);  // = 700.0000000000001
  EXPECT_EQ(parse_step_request(R"({"seconds": 0.001})", 1000.0, 600000), 1U);
}

TEST(HttpJson, StepNeedsExactlyOneOfTicksAndSeconds) {
  for (const char* body : {"{}", R"({"ticks": 1, "seconds": 0.0001})"}) {
    const Refusal r = step_refusal(body);
    EXPECT_EQ(r.status, 400) << body;
    EXPECT_EQ(r.message, "the body needs exactly one of \"ticks\" and \"seconds\"");
  }
  const Refusal extra = step_refusal(R"({"ticks": 1, "tick": 2})");
  EXPECT_EQ(extra.status, 400);
  EXPECT_EQ(extra.message, "unknown key tick (step takes ticks or seconds)");
  EXPECT_EQ(step_refusal("[1]").status, 400);
  EXPECT_EQ(step_refusal("{\"ticks\": ").status, 400);
}

TEST(HttpJson, StepOfZeroNegativeOrTooManyTicksIsOutOfRange) {
  const Refusal zero = step_refusal(R"({"ticks": 0})");
  EXPECT_EQ(zero.status, 400);
  EXPECT_EQ(zero.message, "a step of 0.0 ticks is out of range [1, 600000]");
  EXPECT_EQ(step_refusal(R"({"ticks": -5})").status, 400);
  const Refusal above = step_refusal(R"({"ticks": 600001})");
  EXPECT_EQ(above.status, 400);
  EXPECT_TRUE(contains(above.message, "out of range [1, 600000]")) << above.message;
  EXPECT_EQ(step_refusal(R"({"seconds": 60.0001})").status, 400);
  EXPECT_EQ(step_refusal(R"({"seconds": 0})").status, 400);
  EXPECT_EQ(step_refusal(R"({"seconds": -0.5})").status, 400);
  EXPECT_EQ(step_refusal(R"({"ticks": 18446744073709551615})").status, 400);
  EXPECT_EQ(step_refusal(R"({"seconds": 1e300})").status, 400);
}

TEST(HttpJson, StepTicksMustBeAWholeNumber) {
  const Refusal fraction = step_refusal(R"({"ticks": 1.5})");
  EXPECT_EQ(fraction.status, 400);
  EXPECT_EQ(fraction.message, "ticks must be a whole number, not 1.5");
  EXPECT_EQ(step_refusal(R"({"ticks": 2.0})").status, 400);  // written as a float
  EXPECT_EQ(step_refusal(R"({"ticks": "10"})").message, "ticks must be a whole number, not \"10\"");
  EXPECT_EQ(step_refusal(R"({"seconds": "1"})").message, "seconds must be a number, not string");
  EXPECT_EQ(step_refusal(R"({"seconds": true})").status, 400);
}

TEST(HttpJson, StepSecondsMustBeAWholeNumberOfTicks) {
  const Refusal r = step_refusal(R"({"seconds": 0.00015})");
  EXPECT_EQ(r.status, 400);
  EXPECT_EQ(r.message, "seconds 0.00015 is not a whole number of ticks at 10000.0 Hz");
  EXPECT_EQ(step_refusal(R"({"seconds": 0.00005})").status, 400);  // half a tick
  EXPECT_EQ(step_refusal(R"({"seconds": 0.0015})", 1000.0).status, 400);
}

// --- error_body ----------------------------------------------------------------------------------

TEST(HttpJson, ErrorBodyIsOneLineOfValidJson) {
  const std::string body = error_body("bad \"value\"\nsecond line\r\n\tand a tab");
  ASSERT_FALSE(body.empty());
  EXPECT_EQ(body.back(), '\n');
  EXPECT_EQ(body.find('\n'), body.size() - 1);  // the only newline ends it
  EXPECT_EQ(body.find('\r'), std::string::npos);
  const json j = json::parse(body);
  ASSERT_TRUE(j.is_object());
  EXPECT_EQ(j.size(), 1U);
  EXPECT_EQ(j["error"], "bad \"value\" second line  \tand a tab");
}

TEST(HttpJson, ErrorBodyOfAnHttpErrorCarriesItsMessage) {
  const Refusal r = fault_refusal("{");
  const json j = json::parse(error_body(r.message));
  EXPECT_EQ(j["error"], r.message);
}

}  // namespace
}  // namespace swum::emu
