// firmware_sim/core/scenario.h: scenario files and --inject values (docs/scenarios.md). Every type
// with its keys and defaults, the order of events, each kind of refusal with its exact
// file:line and text, and format_event <-> parse_injection.
#include "core/scenario.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>
#include "test_paths.h"

namespace swum::emu {
namespace {

// What the parser says about TEXT: the ScenarioError's message, or "(accepted)".
template <typename Parse>
std::string refusal(Parse parse, const std::string& text) {
  try {
    (void)parse(text);
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "(accepted)";
}
std::string message_of(const std::string& toml_text) {
  return refusal([](const std::string& t) { return parse_scenario(t, "s.toml"); }, toml_text);
}
std::string injection_message_of(const std::string& text) {
  return refusal([](const std::string& t) { return parse_injection(t); }, text);
}

// One event of a file: [[event]] on line 1, at_s on line 2, type on line 3, KEYS from line 4.
ScenarioEvent single_event(const std::string& type, const std::string& keys) {
  const auto scenario = parse_scenario("[[event]]\nat_s = 1.5\ntype = \"" + type + "\"\n" + keys, "s.toml");
  EXPECT_EQ(scenario.events.size(), 1U);
  return scenario.events.at(0);
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

constexpr auto kKnownTypes =
    "load_step, load_ramp, load_sine, ambient, phase_open, phase_short, over_temperature, voltage_sag, jam, "
    "guide_friction, preload_loss, encoder_stuck, encoder_noise, speed_frozen, speed_bias, speed_noise, "
    "telemetry_silence, modbus_drop, modbus_delay, can_bus_off, clear";
constexpr auto kFaults =
    "phase_open, phase_short, over_temperature, voltage_sag, jam, guide_friction, preload_loss, encoder_stuck, "
    "encoder_noise, speed_frozen, speed_bias, speed_noise, telemetry_silence, modbus_drop, modbus_delay, "
    "can_bus_off";

// Every type with all its keys given (not the defaults), for the round trip.
const std::vector<std::string>& every_type_injected() {
  static const std::vector<std::string> texts = {
      "load_step@0.5:load_n=-2.25",
      "load_ramp@1:to_n=30,duration_s=0.125",
      "load_sine@2:offset_n=10,amplitude_n=-20,frequency_hz=1000,duration_s=3",
      "ambient@0:temperature_c=-40",
      "phase_open@0.25:phase=B,duration_s=0.1",
      "phase_short@3:phase=A",
      "over_temperature@4",
      "voltage_sag@5:factor=0.7,duration_s=1e6",
      "jam@6:position_um=-1234.5,duration_s=0.5",
      "guide_friction@7:factor=10,duration_s=2",
      "preload_loss@8:factor=0,duration_s=0",
      "encoder_stuck@9:duration_s=1",
      "encoder_noise@10:sigma_um=1e-7,duration_s=1",
      "speed_frozen@11:duration_s=0.3333333333333333",
      "speed_bias@12:bias_mm_s=-1000,duration_s=4",
      "speed_noise@13:sigma_mm_s=0.1,duration_s=5",
      "telemetry_silence@14:duration_s=0.2",
      "modbus_drop@15:count=1000000",
      "modbus_delay@16:delay_ms=10000,duration_s=6",
      "can_bus_off@17:duration_s=0.05",
      "clear@1e6:fault=can_bus_off",
  };
  return texts;
}

TEST(Scenario, TypeNamesRoundTripAndFaultsAreTheDocumentedOnes) {
  for (int k = 0; k <= static_cast<int>(EventType::clear); ++k) {
    const auto type = static_cast<EventType>(k);
    const auto back = event_type_from_string(to_string(type));
    ASSERT_TRUE(back.has_value()) << to_string(type);
    EXPECT_EQ(*back, type);
    EXPECT_EQ(is_fault(type), type >= EventType::phase_open && type <= EventType::can_bus_off) << to_string(type);
  }
  EXPECT_FALSE(event_type_from_string("Load_step").has_value());
  EXPECT_FALSE(event_type_from_string("").has_value());
  EXPECT_FALSE(is_fault(EventType::ambient));
  EXPECT_FALSE(is_fault(EventType::clear));
}

TEST(Scenario, EmptyFileIsAnEmptyScenario) {
  const auto scenario = parse_scenario("", "empty.toml");
  EXPECT_EQ(scenario.name, "");
  EXPECT_EQ(scenario.seed, 0U);
  EXPECT_TRUE(scenario.events.empty());
  EXPECT_TRUE(parse_scenario("# only a comment\n\n", "c.toml").events.empty());
}

TEST(Scenario, NameAndSeed) {
  const auto scenario = parse_scenario("name = \"soak 3\"\nseed = 18446744073\n", "s.toml");
  EXPECT_EQ(scenario.name, "soak 3");
  EXPECT_EQ(scenario.seed, 18446744073U);
  EXPECT_EQ(parse_scenario("seed = 0", "s.toml").seed, 0U);
}

TEST(Scenario, LoadEvents) {
  auto e = single_event("load_step", "load_n = 2");
  EXPECT_EQ(e.type, EventType::load_step);
  EXPECT_EQ(e.at_s, 1.5);
  EXPECT_EQ(e.parameters.load_n, 2.0);
  EXPECT_EQ(e.origin, "s.toml:1");

  e = single_event("load_ramp", "to_n = -30.0\nduration_s = 0.25");
  EXPECT_EQ(e.parameters.to_n, -30.0);
  EXPECT_EQ(e.parameters.duration_s, 0.25);

  e = single_event("load_sine", "offset_n = 5\namplitude_n = 2.5\nfrequency_hz = 20");
  EXPECT_EQ(e.parameters.offset_n, 5.0);
  EXPECT_EQ(e.parameters.amplitude_n, 2.5);
  EXPECT_EQ(e.parameters.frequency_hz, 20.0);
  EXPECT_EQ(e.parameters.duration_s, 0.0);  // until the next load event
  e = single_event("load_sine", "offset_n = -15\namplitude_n = 15\nfrequency_hz = 1000\nduration_s = 2");
  EXPECT_EQ(e.parameters.duration_s, 2.0);

  e = single_event("ambient", "temperature_c = 150");
  EXPECT_EQ(e.parameters.temperature_c, 150.0);
}

TEST(Scenario, PhaseAndAmplifierFaults) {
  auto e = single_event("phase_open", "phase = \"B\"");
  EXPECT_EQ(e.parameters.phase, Phase::B);
  EXPECT_EQ(e.parameters.duration_s, 0.0);  // until cleared
  e = single_event("phase_open", "phase = \"A\"\nduration_s = 0.1");
  EXPECT_EQ(e.parameters.phase, Phase::A);
  EXPECT_EQ(e.parameters.duration_s, 0.1);
  e = single_event("phase_short", "phase = \"B\"");
  EXPECT_EQ(e.parameters.phase, Phase::B);
  e = single_event("over_temperature", "");
  EXPECT_EQ(e.type, EventType::over_temperature);
  EXPECT_EQ(e.parameters, EventParameters{});
}

TEST(Scenario, MechanicalFaults) {
  auto e = single_event("voltage_sag", "factor = 0");
  EXPECT_EQ(e.parameters.factor, 0.0);
  EXPECT_EQ(e.parameters.duration_s, 0.0);
  e = single_event("voltage_sag", "factor = 1\nduration_s = 3");
  EXPECT_EQ(e.parameters.factor, 1.0);
  EXPECT_EQ(e.parameters.duration_s, 3.0);

  e = single_event("jam", "");
  EXPECT_FALSE(e.parameters.position_um.has_value());  // where the mover is
  EXPECT_EQ(e.parameters.duration_s, 0.0);
  e = single_event("jam", "position_um = -250.5\nduration_s = 0.2");
  EXPECT_EQ(e.parameters.position_um, -250.5);
  EXPECT_EQ(e.parameters.duration_s, 0.2);

  e = single_event("guide_friction", "factor = 10");
  EXPECT_EQ(e.parameters.factor, 10.0);
  EXPECT_EQ(e.parameters.duration_s, 0.0);
  e = single_event("preload_loss", "factor = 0.4\nduration_s = 1");
  EXPECT_EQ(e.parameters.factor, 0.4);
  EXPECT_EQ(e.parameters.duration_s, 1.0);
}

TEST(Scenario, SensorFaults) {
  auto e = single_event("encoder_stuck", "");
  EXPECT_EQ(e.parameters.duration_s, 0.0);
  e = single_event("encoder_stuck", "duration_s = 0.5");
  EXPECT_EQ(e.parameters.duration_s, 0.5);
  e = single_event("encoder_noise", "sigma_um = 1e4");
  EXPECT_EQ(e.parameters.sigma_um, 1e4);
  EXPECT_EQ(e.parameters.duration_s, 0.0);
  e = single_event("speed_frozen", "");
  EXPECT_EQ(e.parameters.duration_s, 0.0);
  e = single_event("speed_bias", "bias_mm_s = -12.5");
  EXPECT_EQ(e.parameters.bias_mm_s, -12.5);
  EXPECT_EQ(e.parameters.duration_s, 0.0);
  e = single_event("speed_noise", "sigma_mm_s = 2\nduration_s = 4");
  EXPECT_EQ(e.parameters.sigma_mm_s, 2.0);
  EXPECT_EQ(e.parameters.duration_s, 4.0);
}

TEST(Scenario, CommunicationFaultsAndClear) {
  auto e = single_event("telemetry_silence", "duration_s = 0.5");
  EXPECT_EQ(e.parameters.duration_s, 0.5);
  e = single_event("modbus_drop", "");
  EXPECT_EQ(e.parameters.count, 1U);
  e = single_event("modbus_drop", "count = 1000000");
  EXPECT_EQ(e.parameters.count, 1000000U);
  e = single_event("modbus_delay", "delay_ms = 250");
  EXPECT_EQ(e.parameters.delay_ms, 250.0);
  EXPECT_EQ(e.parameters.duration_s, 0.0);
  e = single_event("can_bus_off", "duration_s = 1e6");
  EXPECT_EQ(e.parameters.duration_s, 1e6);
  e = single_event("clear", "fault = \"phase_open\"");
  EXPECT_EQ(e.parameters.fault, EventType::phase_open);
}

TEST(Scenario, EventsSortedByTimeKeepingFileOrderForEqualTimes) {
  const auto scenario = parse_scenario(R"(name = "order"
[[event]]
at_s = 2
type = "load_step"
load_n = 1
[[event]]
at_s = 1
type = "load_step"
load_n = 2
[[event]]
at_s = 2
type = "load_step"
load_n = 3
[[event]]
at_s = 0
type = "over_temperature"
[[event]]
at_s = 2.0
type = "load_step"
load_n = 4
)",
                                       "order.toml");
  ASSERT_EQ(scenario.events.size(), 5U);
  EXPECT_EQ(scenario.events[0].type, EventType::over_temperature);
  EXPECT_EQ(scenario.events[0].origin, "order.toml:14");
  EXPECT_EQ(scenario.events[1].parameters.load_n, 2.0);
  EXPECT_EQ(scenario.events[2].parameters.load_n, 1.0);
  EXPECT_EQ(scenario.events[2].origin, "order.toml:2");
  EXPECT_EQ(scenario.events[3].parameters.load_n, 3.0);
  EXPECT_EQ(scenario.events[4].parameters.load_n, 4.0);
}

TEST(Scenario, InlineArrayOfTablesIsTheSameFormat) {
  const auto scenario = parse_scenario("event = [{ at_s = 1, type = \"jam\" }, { at_s = 0, type = \"speed_frozen\" }]",
                                       "inline.toml");
  ASSERT_EQ(scenario.events.size(), 2U);
  EXPECT_EQ(scenario.events[0].type, EventType::speed_frozen);
  EXPECT_EQ(scenario.events[1].type, EventType::jam);
}

TEST(Scenario, TimesAtTheLimits) {
  EXPECT_EQ(single_event("over_temperature", "").at_s, 1.5);
  EXPECT_EQ(parse_scenario("[[event]]\nat_s = 0\ntype = \"speed_frozen\"", "s.toml").events.at(0).at_s, 0.0);
  EXPECT_EQ(parse_scenario("[[event]]\nat_s = 1e6\ntype = \"speed_frozen\"", "s.toml").events.at(0).at_s, 1e6);
}

TEST(Scenario, SyntaxErrorNamesItsLine) {
  EXPECT_EQ(message_of("name = \"x\"\n[[event]]\nat_s = = 1\n"),
            "s.toml:3: TOML syntax error: Error while parsing value: could not determine value type");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\nat_s = 2\n").rfind("s.toml:3: TOML syntax error: ", 0), 0U);
}

TEST(Scenario, UnknownTypeListsTheKnownOnes) {
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"load_stepp\"\n"),
            std::string("s.toml:3: unknown event type \"load_stepp\" (known: ") + kKnownTypes + ")");
  EXPECT_EQ(message_of("\n[[event]]\nat_s = 1\n"),
            std::string("s.toml:2: event without type (known: ") + kKnownTypes + ")");
  EXPECT_EQ(message_of("[[event]]\ntype = 3\n"), "s.toml:2: event type must be a string, not 3");
}

TEST(Scenario, UnknownKeys) {
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"load_step\"\nload_n = 1\nloadn = 2\n"),
            "s.toml:5: load_step: unknown key loadn (load_step takes: load_n)");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"jam\"\nduration = 2\n"),
            "s.toml:4: jam: unknown key duration (jam takes: position_um, duration_s)");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"over_temperature\"\nduration_s = 2\n"),
            "s.toml:4: over_temperature: unknown key duration_s (over_temperature takes no keys)");
  EXPECT_EQ(message_of("name = \"a\"\nseeds = 3\n"),
            "s.toml:2: unknown top-level key seeds (known: name, seed, event)");
  EXPECT_EQ(message_of("[load]\nn = 3\n"), "s.toml:1: unknown top-level key load (known: name, seed, event)");
}

TEST(Scenario, MissingKeysNameTheEventLine) {
  EXPECT_EQ(message_of("seed = 1\n\n[[event]]\ntype = \"load_step\"\nload_n = 1\n"),
            "s.toml:3: load_step: missing key at_s");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"load_ramp\"\nto_n = 1\n"),
            "s.toml:1: load_ramp: missing key duration_s");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"phase_short\"\n"), "s.toml:1: phase_short: missing key phase");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"telemetry_silence\"\n"),
            "s.toml:1: telemetry_silence: missing key duration_s");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"clear\"\n"), "s.toml:1: clear: missing key fault");
}

TEST(Scenario, WrongValueTypes) {
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"load_step\"\nload_n = \"2\"\n"),
            "s.toml:4: load_step: load_n must be a number, not \"2\"");
  EXPECT_EQ(message_of("[[event]]\nat_s = true\ntype = \"load_step\"\nload_n = 2\n"),
            "s.toml:2: load_step: at_s must be a number, not a boolean");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"modbus_drop\"\ncount = 2.0\n"),
            "s.toml:4: modbus_drop: count must be an integer, not 2.0");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"jam\"\nposition_um = [1]\n"),
            "s.toml:4: jam: position_um must be a number, not an array");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"load_step\"\nload_n = nan\n"),
            "s.toml:4: load_step: load_n must be finite, not nan");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"jam\"\nposition_um = -inf\n"),
            "s.toml:4: jam: position_um must be finite, not -inf");
  EXPECT_EQ(message_of("name = 3\n"), "s.toml:1: name must be a string, not 3");
  EXPECT_EQ(message_of("seed = -1\n"), "s.toml:1: seed must be an integer >= 0, not -1");
  EXPECT_EQ(message_of("seed = 1.5\n"), "s.toml:1: seed must be an integer >= 0, not 1.5");
  EXPECT_EQ(message_of("[event]\nat_s = 1\n"), "s.toml:1: event must be an array of tables ([[event]]), not a table");
  EXPECT_EQ(message_of("event = [1]\n"), "s.toml:1: event must be a table ([[event]]), not 1");
}

TEST(Scenario, OutOfRangeGivesTheRange) {
  EXPECT_EQ(message_of("[[event]]\nat_s = 0.5\ntype = \"load_step\"\nload_n = 40\n"),
            "s.toml:4: load_step: load_n 40 out of range [-30, 30]");
  EXPECT_EQ(message_of("[[event]]\nat_s = -0.1\ntype = \"load_step\"\nload_n = 1\n"),
            "s.toml:2: load_step: at_s -0.1 out of range [0, 1e6]");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1000001\ntype = \"load_step\"\nload_n = 1\n"),
            "s.toml:2: load_step: at_s 1000001 out of range [0, 1e6]");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"load_ramp\"\nto_n = 1\nduration_s = 0\n"),
            "s.toml:5: load_ramp: duration_s 0 out of range (0, 1e6]");
  EXPECT_EQ(
      message_of("[[event]]\nat_s = 1\ntype = \"load_sine\"\noffset_n = 20\namplitude_n = -15\nfrequency_hz = 1\n"),
      "s.toml:1: load_sine: |offset_n| + |amplitude_n| = 35 exceeds 30");
  EXPECT_EQ(
      message_of("[[event]]\nat_s = 1\ntype = \"load_sine\"\noffset_n = 0\namplitude_n = 1\nfrequency_hz = 1001\n"),
      "s.toml:6: load_sine: frequency_hz 1001 out of range (0, 1000]");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"ambient\"\ntemperature_c = -40.5\n"),
            "s.toml:4: ambient: temperature_c -40.5 out of range [-40, 150]");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"voltage_sag\"\nfactor = 1.01\n"),
            "s.toml:4: voltage_sag: factor 1.01 out of range [0, 1]");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"guide_friction\"\nfactor = 11\n"),
            "s.toml:4: guide_friction: factor 11 out of range [0, 10]");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"encoder_noise\"\nsigma_um = 0\n"),
            "s.toml:4: encoder_noise: sigma_um 0 out of range (0, 10000]");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"modbus_drop\"\ncount = 0\n"),
            "s.toml:4: modbus_drop: count 0 out of range [1, 1e6]");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"modbus_delay\"\ndelay_ms = 10000.5\n"),
            "s.toml:4: modbus_delay: delay_ms 10000.5 out of range (0, 10000]");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"speed_frozen\"\nduration_s = -1\n"),
            "s.toml:4: speed_frozen: duration_s -1 out of range [0, 1e6]");
}

TEST(Scenario, BadPhaseAndClearOfANonFault) {
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"phase_open\"\nphase = \"C\"\n"),
            "s.toml:4: phase_open: phase must be \"A\" or \"B\", not \"C\"");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"phase_short\"\nphase = \"a\"\n"),
            "s.toml:4: phase_short: phase must be \"A\" or \"B\", not \"a\"");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"clear\"\nfault = \"load_step\"\n"),
            std::string("s.toml:4: clear: fault \"load_step\" is not a fault (faults: ") + kFaults + ")");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"clear\"\nfault = \"clear\"\n"),
            std::string("s.toml:4: clear: fault \"clear\" is not a fault (faults: ") + kFaults + ")");
  EXPECT_EQ(message_of("[[event]]\nat_s = 1\ntype = \"clear\"\nfault = \"jamm\"\n"),
            std::string("s.toml:4: clear: fault \"jamm\" is not a fault (faults: ") + kFaults + ")");
}

TEST(Scenario, MessagesAreOneLine) {
  EXPECT_EQ(message_of("\"a\\nb\" = 1\n"), "s.toml:1: unknown top-level key a\\x0Ab (known: name, seed, event)");
  EXPECT_EQ(injection_message_of("jam\n@1"),
            std::string("--inject 'jam\\x0A@1': unknown event type \"jam\\x0A\" (known: ") + kKnownTypes + ")");
}

TEST(Scenario, InjectionWithDefaults) {
  const auto e = parse_injection("phase_open@0.25:phase=B,duration_s=0.1");
  EXPECT_EQ(e.type, EventType::phase_open);
  EXPECT_EQ(e.at_s, 0.25);
  EXPECT_EQ(e.parameters.phase, Phase::B);
  EXPECT_EQ(e.parameters.duration_s, 0.1);
  EXPECT_EQ(e.origin, "--inject");

  const auto drop = parse_injection("modbus_drop@3");
  EXPECT_EQ(drop.at_s, 3.0);
  EXPECT_EQ(drop.parameters.count, 1U);
  const auto jam = parse_injection("jam@1e-3");
  EXPECT_EQ(jam.at_s, 1e-3);
  EXPECT_FALSE(jam.parameters.position_um.has_value());
  EXPECT_EQ(parse_injection("clear@2:fault=jam").parameters.fault, EventType::jam);
}

TEST(Scenario, BadInjections) {
  EXPECT_EQ(injection_message_of("load_step"), "--inject 'load_step': expected NAME@SECONDS[:key=value,...]");
  EXPECT_EQ(injection_message_of(""), "--inject '': expected NAME@SECONDS[:key=value,...]");
  EXPECT_EQ(injection_message_of("stall@1"),
            std::string("--inject 'stall@1': unknown event type \"stall\" (known: ") + kKnownTypes + ")");
  EXPECT_EQ(injection_message_of("load_step@soon:load_n=1"),
            "--inject 'load_step@soon:load_n=1': load_step: at_s must be a number, not \"soon\"");
  EXPECT_EQ(injection_message_of("load_step@:load_n=1"),
            "--inject 'load_step@:load_n=1': load_step: at_s must be a number, not \"\"");
  EXPECT_EQ(injection_message_of("load_step@+1:load_n=1"),
            "--inject 'load_step@+1:load_n=1': load_step: at_s must be a number, not \"+1\"");
  EXPECT_EQ(injection_message_of("load_step@-1:load_n=1"),
            "--inject 'load_step@-1:load_n=1': load_step: at_s -1 out of range [0, 1e6]");
  EXPECT_EQ(injection_message_of("load_step@nan:load_n=1"),
            "--inject 'load_step@nan:load_n=1': load_step: at_s must be finite, not nan");
  EXPECT_EQ(injection_message_of("load_step@1e999:load_n=1"),
            "--inject 'load_step@1e999:load_n=1': load_step: at_s must be finite, not inf");
  EXPECT_EQ(injection_message_of("load_step@1:force=1"),
            "--inject 'load_step@1:force=1': load_step: unknown key force (load_step takes: load_n)");
  EXPECT_EQ(injection_message_of("load_step@1"), "--inject 'load_step@1': load_step: missing key load_n");
  EXPECT_EQ(injection_message_of("load_step@1:"), "--inject 'load_step@1:': load_step: expected key=value, not \"\"");
  EXPECT_EQ(injection_message_of("load_step@1:load_n=1,"),
            "--inject 'load_step@1:load_n=1,': load_step: expected key=value, not \"\"");
  EXPECT_EQ(injection_message_of("load_step@1:load_n"),
            "--inject 'load_step@1:load_n': load_step: expected key=value, not \"load_n\"");
  EXPECT_EQ(injection_message_of("load_step@1:=3"),
            "--inject 'load_step@1:=3': load_step: expected key=value, not \"=3\"");
  EXPECT_EQ(injection_message_of("load_step@1:load_n=1,load_n=2"),
            "--inject 'load_step@1:load_n=1,load_n=2': load_step: key load_n given twice");
  EXPECT_EQ(injection_message_of("load_step@1:load_n= 2"),
            "--inject 'load_step@1:load_n= 2': load_step: load_n must be a number, not \" 2\"");
  EXPECT_EQ(injection_message_of("load_step@1:load_n=31"),
            "--inject 'load_step@1:load_n=31': load_step: load_n 31 out of range [-30, 30]");
  EXPECT_EQ(injection_message_of("phase_short@1:phase=C"),
            "--inject 'phase_short@1:phase=C': phase_short: phase must be \"A\" or \"B\", not \"C\"");
  EXPECT_EQ(injection_message_of("modbus_drop@1:count=2.5"),
            "--inject 'modbus_drop@1:count=2.5': modbus_drop: count must be an integer, not 2.5");
  EXPECT_EQ(injection_message_of("clear@1:fault=ambient"),
            std::string("--inject 'clear@1:fault=ambient': clear: fault \"ambient\" is not a fault (faults: ") +
                kFaults + ")");
}

TEST(Scenario, FormatEventRoundTripsEveryType) {
  ASSERT_EQ(every_type_injected().size(), static_cast<std::size_t>(EventType::clear) + 1);
  for (std::size_t k = 0; k < every_type_injected().size(); ++k) {
    const std::string& text = every_type_injected()[k];
    SCOPED_TRACE(text);
    const auto event = parse_injection(text);
    EXPECT_EQ(event.type, static_cast<EventType>(k));
    EXPECT_EQ(format_event(event), text);  // the texts are written in the canonical form
    EXPECT_EQ(parse_injection(format_event(event)), event);
  }
}

TEST(Scenario, FormatEventWritesDefaultsAndShortestNumbers) {
  EXPECT_EQ(format_event(parse_injection("jam@0")), "jam@0:duration_s=0");
  EXPECT_EQ(format_event(parse_injection("modbus_drop@2.50")), "modbus_drop@2.5:count=1");
  EXPECT_EQ(format_event(parse_injection("voltage_sag@1000000:factor=0.5")), "voltage_sag@1e6:factor=0.5,duration_s=0");
  EXPECT_EQ(format_event(parse_injection("over_temperature@0.1")), "over_temperature@0.1");
  // Events from a file format the same way, and read back equal but for the origin.
  const auto from_file = single_event("speed_noise", "sigma_mm_s = 0.30000000000000004");
  EXPECT_EQ(format_event(from_file), "speed_noise@1.5:sigma_mm_s=0.30000000000000004,duration_s=0");
  auto back = parse_injection(format_event(from_file));
  back.origin = from_file.origin;
  EXPECT_EQ(back, from_file);
}

TEST(Scenario, CommittedExampleParses) {
  const auto example = parse_scenario(read_text(swum::test::source_path("config/scenarios/load_step_and_faults.toml")),
                                      "load_step_and_faults.toml");
  EXPECT_EQ(example.name, "load step and faults");
  EXPECT_EQ(example.seed, 7U);
  ASSERT_GE(example.events.size(), 5U);
  EXPECT_EQ(example.events.front().type, EventType::load_step);
}

// Every ```toml block of docs/scenarios.md is a valid scenario file.
TEST(Scenario, DocsExamplesParse) {
  const std::string docs = read_text(swum::test::source_path("docs/scenarios.md"));
  std::size_t blocks = 0;
  for (auto start = docs.find("```toml\n"); start != std::string::npos; start = docs.find("```toml\n", start)) {
    start += 8;
    const auto end = docs.find("```", start);
    ASSERT_NE(end, std::string::npos);
    const std::string block = docs.substr(start, end - start);
    EXPECT_NO_THROW((void)parse_scenario(block, "docs/scenarios.md")) << block;
    ++blocks;
    start = end + 3;
  }
  EXPECT_EQ(blocks, 2U);
}

// --- make_event and event_keys (the HTTP API's way in) -----------------------------------------

using Values = std::vector<std::pair<std::string, EventValue>>;

EventValue integer_value(std::int64_t v) {
  EventValue e;
  e.kind = EventValue::Kind::integer;
  e.integer = v;
  return e;
}
EventValue floating_value(double v) {
  EventValue e;
  e.kind = EventValue::Kind::floating;
  e.floating = v;
  return e;
}
EventValue name_value(const std::string& v) {
  EventValue e;
  e.kind = EventValue::Kind::name;
  e.name = v;
  return e;
}

std::string make_event_message(EventType type, const Values& values, double at_s = 0.0) {
  try {
    (void)make_event(type, values, at_s, "http");
  } catch (const ScenarioError& e) {
    return e.what();
  }
  return "(accepted)";
}

// The values of an --inject text's key=value pairs as a program gives them: a name, a whole
// number as an integer, any other number as a floating one.
Values values_of_injection(const std::string& text) {
  Values values;
  const auto colon = text.find(':');
  if (colon == std::string::npos) return values;
  std::stringstream pairs(text.substr(colon + 1));
  for (std::string pair; std::getline(pairs, pair, ',');) {
    const auto equals = pair.find('=');
    const std::string key = pair.substr(0, equals);
    const std::string value = pair.substr(equals + 1);
    if (value.find_first_not_of("-0123456789") == std::string::npos) {
      values.emplace_back(key, integer_value(std::stoll(value)));
    } else if (value.find_first_not_of("-0123456789.e") == std::string::npos) {
      values.emplace_back(key, floating_value(std::stod(value)));
    } else {
      values.emplace_back(key, name_value(value));
    }
  }
  return values;
}

TEST(ScenarioMakeEvent, EveryTypeGivesTheEventTheInjectionGives) {
  for (const std::string& text : every_type_injected()) {
    SCOPED_TRACE(text);
    ScenarioEvent expected = parse_injection(text);
    expected.origin = "http";
    EXPECT_EQ(make_event(expected.type, values_of_injection(text), expected.at_s, "http"), expected);
  }
}

TEST(ScenarioMakeEvent, OptionalKeysTakeTheirDefaults) {
  const ScenarioEvent open = make_event(EventType::phase_open, {{"phase", name_value("B")}}, 0.0, "http");
  EXPECT_EQ(open.parameters.phase, Phase::B);
  EXPECT_EQ(open.parameters.duration_s, 0.0);
  EXPECT_EQ(make_event(EventType::modbus_drop, {}, 0.0, "http").parameters.count, 1U);
  EXPECT_FALSE(make_event(EventType::jam, {}, 2.5, "http").parameters.position_um.has_value());
  EXPECT_EQ(make_event(EventType::jam, {}, 2.5, "http").at_s, 2.5);
  EXPECT_EQ(make_event(EventType::jam, {}, 2.5, "origin").origin, "origin");
}

TEST(ScenarioMakeEvent, PhaseMustBeAOrB) {
  EXPECT_EQ(make_event_message(EventType::phase_open, {{"phase", name_value("C")}}),
            "phase_open: phase must be \"A\" or \"B\", not \"C\"");
  EXPECT_EQ(make_event_message(EventType::phase_short, {{"phase", name_value("a")}}),
            "phase_short: phase must be \"A\" or \"B\", not \"a\"");
  EXPECT_EQ(make_event_message(EventType::phase_short, {{"phase", integer_value(1)}}),
            "phase_short: phase must be \"A\" or \"B\", not 1");
}

TEST(ScenarioMakeEvent, NumbersOutOfRangeGiveTheRange) {
  EXPECT_EQ(make_event_message(EventType::voltage_sag, {{"factor", floating_value(1.01)}}),
            "voltage_sag: factor 1.01 out of range [0, 1]");
  EXPECT_EQ(make_event_message(EventType::load_step, {{"load_n", integer_value(40)}}),
            "load_step: load_n 40 out of range [-30, 30]");
  EXPECT_EQ(make_event_message(EventType::encoder_noise, {{"sigma_um", integer_value(0)}}),
            "encoder_noise: sigma_um 0 out of range (0, 10000]");
  EXPECT_EQ(make_event_message(EventType::modbus_drop, {{"count", integer_value(0)}}),
            "modbus_drop: count 0 out of range [1, 1e6]");
  EXPECT_EQ(make_event_message(EventType::speed_frozen, {{"duration_s", integer_value(-1)}}),
            "speed_frozen: duration_s -1 out of range [0, 1e6]");
  EXPECT_EQ(make_event_message(EventType::speed_frozen, {{"duration_s", floating_value(-1.0)}}),
            "speed_frozen: duration_s -1.0 out of range [0, 1e6]");  // as a file's "duration_s = -1.0"
  EXPECT_EQ(make_event_message(EventType::load_step, {{"load_n", integer_value(1)}}, -0.1),
            "load_step: at_s -0.1 out of range [0, 1e6]");
  EXPECT_EQ(make_event_message(EventType::load_sine, {{"offset_n", integer_value(20)},
                                                      {"amplitude_n", integer_value(-15)},
                                                      {"frequency_hz", integer_value(1)}}),
            "load_sine: |offset_n| + |amplitude_n| = 35 exceeds 30");
}

TEST(ScenarioMakeEvent, WrongKindsOfValueAreRefused) {
  EXPECT_EQ(make_event_message(EventType::load_step, {{"load_n", name_value("2")}}),
            "load_step: load_n must be a number, not \"2\"");
  EXPECT_EQ(make_event_message(EventType::modbus_drop, {{"count", floating_value(2.0)}}),
            "modbus_drop: count must be an integer, not 2.0");
  EXPECT_EQ(make_event_message(EventType::load_step, {{"load_n", floating_value(std::nan(""))}}),
            "load_step: load_n must be finite, not nan");
  EXPECT_EQ(make_event_message(EventType::jam, {{"position_um", floating_value(-HUGE_VAL)}}),
            "jam: position_um must be finite, not -inf");
  EXPECT_EQ(make_event_message(EventType::clear, {{"fault", name_value("load_step")}}),
            std::string("clear: fault \"load_step\" is not a fault (faults: ") + kFaults + ")");
}

TEST(ScenarioMakeEvent, MissingUnknownAndRepeatedKeys) {
  EXPECT_EQ(make_event_message(EventType::load_ramp, {{"to_n", integer_value(1)}}),
            "load_ramp: missing key duration_s");
  EXPECT_EQ(make_event_message(EventType::clear, {}), "clear: missing key fault");
  EXPECT_EQ(make_event_message(EventType::jam, {{"duration", integer_value(2)}}),
            "jam: unknown key duration (jam takes: position_um, duration_s)");
  EXPECT_EQ(make_event_message(EventType::over_temperature, {{"duration_s", integer_value(2)}}),
            "over_temperature: unknown key duration_s (over_temperature takes no keys)");
  EXPECT_EQ(make_event_message(EventType::load_step, {{"load_n", integer_value(1)}, {"load_n", integer_value(2)}}),
            "load_step: key load_n given twice");
}

// The same refusal from a file and from make_event: the file's message is "s.toml:LINE: " + it.
TEST(ScenarioMakeEvent, MessagesAreTheFilesWithoutTheWhere) {
  struct Case {
    EventType type;
    std::string toml_keys;
    Values values;
  };
  const std::vector<Case> cases = {
      {EventType::phase_open, "phase = \"C\"\n", {{"phase", name_value("C")}}},
      {EventType::guide_friction, "factor = 11\n", {{"factor", integer_value(11)}}},
      {EventType::modbus_delay, "delay_ms = 10000.5\n", {{"delay_ms", floating_value(10000.5)}}},
      {EventType::telemetry_silence, "", {}},
      {EventType::load_step, "load_n = 1\nloadn = 2\n", {{"load_n", integer_value(1)}, {"loadn", integer_value(2)}}},
  };
  for (const Case& c : cases) {
    const std::string from_file = message_of("[[event]]\nat_s = 1\ntype = \"" + std::string(to_string(c.type)) +
                                             "\"\n" + c.toml_keys);
    const auto where_end = from_file.find(": ");
    ASSERT_NE(where_end, std::string::npos) << from_file;
    EXPECT_EQ(make_event_message(c.type, c.values, 1.0), from_file.substr(where_end + 2));
  }
}

bool same_key(const EventKey& k, const std::string& name, const std::string& kind, bool required) {
  return k.name == name && k.kind == kind && k.required == required;
}

TEST(ScenarioEventKeys, KeysOfAFaultWithTheirKindsRangesAndDefaults) {
  const std::vector<EventKey> open = event_keys(EventType::phase_open);
  ASSERT_EQ(open.size(), 2U);
  EXPECT_TRUE(same_key(open[0], "phase", "phase", true));
  EXPECT_TRUE(same_key(open[1], "duration_s", "number", false));
  EXPECT_EQ(open[1].min, 0.0);
  EXPECT_EQ(open[1].max, 1e6);
  EXPECT_FALSE(open[1].min_open);
  const std::vector<EventKey> noise = event_keys(EventType::encoder_noise);
  ASSERT_EQ(noise.size(), 2U);
  EXPECT_TRUE(same_key(noise[0], "sigma_um", "number", true));
  EXPECT_TRUE(noise[0].min_open);  // (0, 1e4]
  EXPECT_EQ(noise[0].max, 1e4);
  const std::vector<EventKey> drop = event_keys(EventType::modbus_drop);
  ASSERT_EQ(drop.size(), 1U);
  EXPECT_TRUE(same_key(drop[0], "count", "integer", false));
  EXPECT_EQ(drop[0].min, 1.0);
  EXPECT_EQ(drop[0].max, 1e6);
  const std::vector<EventKey> jam = event_keys(EventType::jam);
  ASSERT_EQ(jam.size(), 2U);
  EXPECT_TRUE(same_key(jam[0], "position_um", "number", false));
  EXPECT_EQ(jam[0].min, -1e6);
  EXPECT_TRUE(event_keys(EventType::over_temperature).empty());
  const std::vector<EventKey> clear = event_keys(EventType::clear);
  ASSERT_EQ(clear.size(), 1U);
  EXPECT_TRUE(same_key(clear[0], "fault", "fault", true));
}

// event_keys lists what the file parser takes, in its order ("TYPE takes: ...").
TEST(ScenarioEventKeys, NamesAreTheKeysTheFileTakes) {
  for (int k = 0; k <= static_cast<int>(EventType::clear); ++k) {
    const auto type = static_cast<EventType>(k);
    std::string names;
    for (const EventKey& key : event_keys(type)) names += (names.empty() ? "" : ", ") + key.name;
    const std::string message = message_of("[[event]]\nat_s = 1\ntype = \"" + std::string(to_string(type)) +
                                           "\"\nzzz = 1\n");
    const std::string takes = names.empty() ? " takes no keys)" : " takes: " + names + ")";
    EXPECT_NE(message.find(std::string(to_string(type)) + takes), std::string::npos) << message;
  }
}

TEST(ScenarioEventKeys, EveryNumberRangeIsFiniteAndOrdered) {
  for (int k = 0; k <= static_cast<int>(EventType::clear); ++k) {
    const auto type = static_cast<EventType>(k);
    for (const EventKey& key : event_keys(type)) {
      if (key.kind != "number" && key.kind != "integer") continue;
      EXPECT_TRUE(std::isfinite(key.min) && std::isfinite(key.max)) << to_string(type) << " " << key.name;
      EXPECT_LT(key.min, key.max) << to_string(type) << " " << key.name;
    }
  }
}

}  // namespace
}  // namespace swum::emu
