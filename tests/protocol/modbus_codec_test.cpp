#include "modbus_codec.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>
#include "test_paths.h"

namespace swum::protocol::modbus {
namespace {

std::vector<std::uint8_t> read_pdu(std::uint8_t function, std::uint16_t address, std::uint16_t quantity) {
  return {function, static_cast<std::uint8_t>(address >> 8), static_cast<std::uint8_t>(address),
          static_cast<std::uint8_t>(quantity >> 8), static_cast<std::uint8_t>(quantity)};
}
std::vector<std::uint8_t> write_multiple(std::uint16_t address, const std::vector<std::uint16_t>& values) {
  std::vector<std::uint8_t> pdu{kWriteMultipleRegisters,
                                static_cast<std::uint8_t>(address >> 8),
                                static_cast<std::uint8_t>(address),
                                0,
                                static_cast<std::uint8_t>(values.size()),
                                static_cast<std::uint8_t>(2 * values.size())};
  for (auto v : values) {
    pdu.push_back(static_cast<std::uint8_t>(v >> 8));
    pdu.push_back(static_cast<std::uint8_t>(v));
  }
  return pdu;
}
Decision run(const std::vector<std::uint8_t>& pdu) {
  Request r;
  Reason why;
  Decision d;
  d.exception = parse_request(pdu, r, &why);
  d.reason = why;
  if (d.exception) return d;
  return decide(r, AmplifierLimits{});
}

// MBAP header (transaction 0x1234, protocol id, length field, unit 1) + PDU, as libmodbus frames it.
std::vector<std::uint8_t> adu(std::uint16_t protocol_id, std::uint16_t length_field,
                              const std::vector<std::uint8_t>& pdu) {
  std::vector<std::uint8_t> a{0x12,
                              0x34,
                              static_cast<std::uint8_t>(protocol_id >> 8),
                              static_cast<std::uint8_t>(protocol_id),
                              static_cast<std::uint8_t>(length_field >> 8),
                              static_cast<std::uint8_t>(length_field),
                              1};
  for (const std::uint8_t b : pdu) a.push_back(b);  // (insert: a false -Warray-bounds in GCC 12)
  return a;
}

TEST(MbapHeader, ProtocolIdZeroAndALengthThatCountsUnitAndPduIsValid) {
  const auto pdu = read_pdu(kReadInputRegisters, 0, 1);
  const MbapHeaderCheck whole = check_mbap_header(adu(0, 6, pdu));
  EXPECT_TRUE(whole.valid);
  EXPECT_EQ(whole.surplus_bytes, 0U);
  EXPECT_TRUE(check_mbap_header(adu(0, 2, {0x2b})).valid);  // the shortest: unit id + function code
}

TEST(MbapHeader, ALongerLengthFieldAnnouncesTheRestOfTheRequest) {
  // FC43/14 Read Device Identification: libmodbus frames the code alone; the MBAP length counts
  // its 3-byte body, which the server must read as part of this request.
  const MbapHeaderCheck device_id = check_mbap_header(adu(0, 5, {0x2b}));
  EXPECT_TRUE(device_id.valid);
  EXPECT_EQ(device_id.surplus_bytes, 3U);
  // Up to a whole ADU (260 bytes = 6 + a length field of 254), not beyond.
  EXPECT_EQ(check_mbap_header(adu(0, 254, read_pdu(kReadInputRegisters, 0, 1))).surplus_bytes, 248U);
  EXPECT_FALSE(check_mbap_header(adu(0, 255, read_pdu(kReadInputRegisters, 0, 1))).valid);
  EXPECT_FALSE(check_mbap_header(adu(0, 0xFFFF, read_pdu(kReadInputRegisters, 0, 1))).valid);
}

TEST(MbapHeader, AnotherProtocolIdOrAShorterLengthIsNotValid) {
  const auto pdu = read_pdu(kReadInputRegisters, 0, 1);
  EXPECT_FALSE(check_mbap_header(adu(1, 6, pdu)).valid);       // not Modbus
  EXPECT_FALSE(check_mbap_header(adu(0xFFFF, 6, pdu)).valid);  // not Modbus
  EXPECT_FALSE(check_mbap_header(adu(0, 5, pdu)).valid);       // fewer bytes than framed
  EXPECT_FALSE(check_mbap_header(adu(0, 0, pdu)).valid);
  const auto whole = adu(0, 6, pdu);
  EXPECT_FALSE(check_mbap_header(std::span<const std::uint8_t>(whole.data(), 7)).valid);  // no function code
  EXPECT_FALSE(check_mbap_header({}).valid);
}

TEST(RegisterMap, ReadsWithinTheTablesAreAccepted) {
  EXPECT_EQ(run(read_pdu(kReadHoldingRegisters, 0, holding::kCount)).exception, kNoException);
  EXPECT_EQ(run(read_pdu(kReadInputRegisters, 0, input::kCount)).exception, kNoException);
  EXPECT_EQ(run(read_pdu(kReadInputRegisters, input::kSpeed, 2)).exception, kNoException);
}

TEST(RegisterMap, BadAddressesAndQuantities) {
  EXPECT_EQ(run(read_pdu(kReadHoldingRegisters, 0, holding::kCount + 1)).exception, kIllegalDataAddress);
  EXPECT_EQ(run(read_pdu(kReadInputRegisters, 200, 1)).exception, kIllegalDataAddress);
  EXPECT_EQ(run(read_pdu(kReadInputRegisters, 0, 0)).exception, kIllegalDataValue);
  EXPECT_EQ(run(read_pdu(kReadInputRegisters, 0, 126)).exception, kIllegalDataValue);
  const Decision half = run(read_pdu(kReadInputRegisters, input::kSpeed + 1, 1));
  EXPECT_EQ(half.exception, kIllegalDataAddress);
  EXPECT_EQ(half.reason, Reason::split_value);
  EXPECT_EQ(run(read_pdu(kReadInputRegisters, input::kSpeed, 1)).exception, kIllegalDataAddress);
  EXPECT_EQ(run({0x2B, 0x0E, 0x01, 0x00}).exception, kIllegalFunction);         // device identification
  EXPECT_EQ(run({kReadInputRegisters, 0, 0, 0}).exception, kIllegalDataValue);  // short
}

TEST(RegisterMap, WriteMultipleBecomesOneCommand) {
  // frequency 40123.456 Hz, amplitude 400.0 V, phase -90.00 deg
  const std::uint32_t mhz = 40123456;
  const Decision d = run(write_multiple(holding::kFrequency, {static_cast<std::uint16_t>(mhz >> 16),
                                                              static_cast<std::uint16_t>(mhz & 0xFFFF), 4000,
                                                              static_cast<std::uint16_t>(-9000)}));
  ASSERT_EQ(d.exception, kNoException);
  ASSERT_TRUE(d.has_command);
  EXPECT_EQ(d.command.fields, Command::kFrequency | Command::kAmplitude | Command::kPhase);
  EXPECT_NEAR(d.command.frequency_hz, 40123.456, 1e-6);
  EXPECT_NEAR(d.command.amplitude_v, 400.0, 1e-9);
  EXPECT_NEAR(d.command.phase_deg, -90.0, 1e-9);
  EXPECT_EQ(d.command.source, CommandSource::modbus);
}

TEST(RegisterMap, WriteSingleCommandRegister) {
  const Decision d = run({kWriteSingleRegister, 0, 0, 0, 1});
  ASSERT_TRUE(d.has_command);
  EXPECT_EQ(d.command.action, Action::enable);
  const Decision bad = run({kWriteSingleRegister, 0, 0, 0, 7});
  EXPECT_EQ(bad.exception, kIllegalDataValue);
  EXPECT_EQ(bad.reason, Reason::unknown_command);
  EXPECT_FALSE(bad.has_command);
}

TEST(RegisterMap, OutOfRangeValuesAreIllegalDataValue) {
  const Decision amp = run({kWriteSingleRegister, 0, holding::kAmplitude, 0x1B, 0x58});  // 7000 = 700 V
  EXPECT_EQ(amp.exception, kIllegalDataValue);
  EXPECT_EQ(amp.reason, Reason::amplitude_out_of_range);
  const std::uint32_t mhz = 60000000;
  const Decision f = run(write_multiple(holding::kFrequency, {static_cast<std::uint16_t>(mhz >> 16),
                                                              static_cast<std::uint16_t>(mhz & 0xFFFF)}));
  EXPECT_EQ(f.reason, Reason::frequency_out_of_range);
}

TEST(RegisterMap, HalfOfA32BitValueIsRejected) {
  const Decision d = run({kWriteSingleRegister, 0, holding::kFrequency, 0, 1});
  EXPECT_EQ(d.exception, kIllegalDataAddress);
  EXPECT_EQ(d.reason, Reason::split_value);
}

TEST(RegisterMap, InconsistentByteCountIsIllegalDataValue) {
  auto pdu = write_multiple(holding::kAmplitude, {100});
  pdu[5] = 4;  // byte count does not match quantity 1
  EXPECT_EQ(run(pdu).exception, kIllegalDataValue);
  EXPECT_EQ(run(pdu).reason, Reason::wrong_length);
}

// The JSON description and the code agree: encode a telemetry snapshot with the code and decode
// every input register with the JSON's address/type/scale.
double decode(const nlohmann::json& entry, std::span<const std::uint16_t> regs) {
  const std::string type = entry["type"];
  const unsigned a = entry["address"];
  const double scale = entry["scale"];
  double raw = 0;
  if (type == "uint16") raw = regs[a];
  else if (type == "int16") raw = static_cast<std::int16_t>(regs[a]);
  else if (type == "uint32") raw = (static_cast<std::uint32_t>(regs[a]) << 16) | regs[a + 1];
  else if (type == "int32") raw = static_cast<std::int32_t>((static_cast<std::uint32_t>(regs[a]) << 16) | regs[a + 1]);
  else ADD_FAILURE() << type;
  return raw * scale;
}

nlohmann::json load_map() {
  std::ifstream in(swum::test::source_path("config/modbus_registers.json"));
  EXPECT_TRUE(in.good());
  return nlohmann::json::parse(in);
}

TEST(RegisterMapJson, InputRegistersAgreeWithTheCode) {
  const nlohmann::json map = load_map();
  Telemetry t;
  t.state = AmpState::enabled;
  t.fault = FaultCode::command_timeout;
  t.enable_line = true;
  t.at_setpoint = false;
  t.applied_commands = 123456;
  t.speed_m_s = -0.198449;
  t.position_m = 0.012345;
  t.tip_normal_um = 2.945;
  t.tip_tangential_um = 1.062;
  t.output.frequency_hz = 40123.456;
  t.output.amplitude_v = 399.9;
  t.output.phase_deg = -90.25;
  t.output.load_n = 1.234;
  t.tick = 987654;
  t.sim_time_s = 98.765;
  t.stats.lateness_p50_ns = 3000;
  t.stats.lateness_p99_ns = 12000;
  t.stats.lateness_p999_ns = 45000;
  t.stats.lateness_max_ns = 90000;
  t.stats.compute_p99_ns = 31000;
  t.stats.compute_max_ns = 52000;
  t.stats.overruns = 77;
  t.tick_speed_m_s = 0.2;
  t.last_sequence = 4242;
  t.external_clock = true;
  t.electrical = {0.1234, 0.0987, 12.34, -56.78, -3.21, 4.56, 9.87, 6.54};
  t.stator_temperature_c = 23.45;
  t.amplifier_output = {0.0745, 0.0872, -2.43, -50.12, 199.4, 187.3};
  std::array<std::uint16_t, input::kCount> regs{};
  fill_input(t, RejectSnapshot{Reason::bad_checksum, 70000}, regs);
  const std::map<std::string, double> expected{{"status", 1 + 4 + 8},
                                               {"state", 1},
                                               {"fault_code", 1},
                                               {"last_reject_reason", 7},
                                               {"reject_count", 70000},
                                               {"applied_commands", 123456},
                                               {"speed", -0.198449},
                                               {"position", 0.012345},
                                               {"tip_normal_amplitude", 2.945},
                                               {"tip_tangential_amplitude", 1.062},
                                               {"frequency_output", 40123.456},
                                               {"amplitude_output", 399.9},
                                               {"phase_output", -90.25},
                                               {"load_output", 1.234},
                                               {"tick", 987654},
                                               {"sim_time", 98.765},
                                               {"lateness_p50", 3},
                                               {"lateness_p99", 12},
                                               {"lateness_p999", 45},
                                               {"lateness_max", 90},
                                               {"compute_p99", 31},
                                               {"compute_max", 52},
                                               {"overruns", 77},
                                               {"tick_speed", 0.2},
                                               {"last_sequence", 4242},
                                               {"clock", 1},
                                               {"current_a", 0.1234},
                                               {"current_b", 0.0987},
                                               {"phase_a", 12.34},
                                               {"phase_b", -56.78},
                                               {"motional_phase_a", -3.21},
                                               {"motional_phase_b", 4.56},
                                               {"power_a", 9.87},
                                               {"power_b", 6.54},
                                               {"stator_temperature", 23.45},
                                               {"amplifier_current_a", 0.0745},
                                               {"amplifier_current_b", 0.0872},
                                               {"amplifier_phase_a", -2.43},
                                               {"amplifier_phase_b", -50.12},
                                               {"terminal_amplitude_a", 199.4},
                                               {"terminal_amplitude_b", 187.3}};
  EXPECT_EQ(map["input_registers"].size(), expected.size());
  unsigned words = 0;
  for (const auto& entry : map["input_registers"]) {
    const std::string name = entry["name"];
    ASSERT_TRUE(expected.contains(name)) << name;
    EXPECT_NEAR(decode(entry, regs), expected.at(name), 1e-6 + 1e-9 * std::abs(expected.at(name))) << name;
    const bool wide = entry["type"] == "uint32" || entry["type"] == "int32";
    EXPECT_EQ(is_u32_start_input(entry["address"]), wide) << name;
    words += wide ? 2 : 1;
  }
  EXPECT_EQ(words, input::kCount);
}

// The electrical registers saturate at their type's range like the others (a current beyond
// 6.5535 A, a power beyond 327.67 W, a non-finite value: 0), and decode_input reads them back.
TEST(RegisterMap, ElectricalRegistersSaturateAndDecode) {
  Telemetry t;
  t.electrical = {7.0, -0.5, 180.0, -180.0, std::nan(""), 0.004, 400.0, -400.0};
  t.stator_temperature_c = -300.0;
  std::array<std::uint16_t, input::kCount> regs{};
  fill_input(t, RejectSnapshot{}, regs);
  EXPECT_EQ(regs[input::kCurrentA], 65535);
  EXPECT_EQ(regs[input::kCurrentB], 0);
  EXPECT_EQ(regs[input::kPhaseA], 18000);
  EXPECT_EQ(static_cast<std::int16_t>(regs[input::kPhaseB]), -18000);
  EXPECT_EQ(regs[input::kMotionalPhaseA], 0);
  EXPECT_EQ(regs[input::kMotionalPhaseB], 0);
  EXPECT_EQ(regs[input::kPowerA], 32767);
  EXPECT_EQ(static_cast<std::int16_t>(regs[input::kPowerB]), -32768);
  EXPECT_EQ(static_cast<std::int16_t>(regs[input::kStatorTemperature]), -30000);
  const Telemetry back = decode_input(regs).telemetry;
  EXPECT_DOUBLE_EQ(back.electrical.current_a_a, 6.5535);
  EXPECT_DOUBLE_EQ(back.electrical.phase_b_deg, -180.0);
  EXPECT_DOUBLE_EQ(back.electrical.power_b_w, -327.68);
  EXPECT_DOUBLE_EQ(back.stator_temperature_c, -300.0);
}

TEST(RegisterMapJson, HoldingRegistersAgreeWithTheCode) {
  const nlohmann::json map = load_map();
  Telemetry t;
  t.setpoints.frequency_hz = 40400.5;
  t.setpoints.amplitude_v = 321.4;
  t.setpoints.phase_deg = -45.5;
  t.setpoints.load_n = -2.5;
  t.setpoints.frequency_slew_hz_per_s = 1e6;
  t.setpoints.amplitude_slew_v_per_s = 1e5;
  std::array<std::uint16_t, holding::kCount> regs{};
  fill_holding(t, regs);
  const std::map<std::string, double> expected{
      {"command", 0},       {"frequency_setpoint", 40400.5}, {"amplitude_setpoint", 321.4}, {"phase_setpoint", -45.5},
      {"load_force", -2.5}, {"frequency_slew", 1e6},         {"amplitude_slew", 1e5},       {"advance", 0}};
  unsigned words = 0;
  for (const auto& entry : map["holding_registers"]) {
    const std::string name = entry["name"];
    ASSERT_TRUE(expected.contains(name)) << name;
    EXPECT_NEAR(decode(entry, regs), expected.at(name), 1e-6) << name;
    const bool wide = entry["type"] == "uint32";
    EXPECT_EQ(is_u32_start_holding(entry["address"]), wide) << name;
    words += wide ? 2 : 1;
    // Writing the same raw registers back yields the same physical value.
    std::vector<std::uint16_t> values(regs.begin() + static_cast<long>(entry["address"]),
                                      regs.begin() + static_cast<long>(entry["address"]) + (wide ? 2 : 1));
    const Decision d = run(write_multiple(entry["address"], values));
    ASSERT_EQ(d.exception, kNoException) << name;
    if (name == "advance") {  // a step, not a command (docs/protocols.md, "Lockstep")
      EXPECT_FALSE(d.has_command);
      EXPECT_EQ(d.advance_ticks, expected.at(name));
      continue;
    }
    ASSERT_TRUE(d.has_command) << name;
    const Command& c = d.command;
    const std::map<std::string, double> written{{"command", static_cast<double>(c.action)},
                                                {"frequency_setpoint", c.frequency_hz},
                                                {"amplitude_setpoint", c.amplitude_v},
                                                {"phase_setpoint", c.phase_deg},
                                                {"load_force", c.load_n},
                                                {"frequency_slew", c.frequency_slew_hz_per_s},
                                                {"amplitude_slew", c.amplitude_slew_v_per_s}};
    EXPECT_NEAR(written.at(name), expected.at(name), 1e-6) << name;
  }
  EXPECT_EQ(words, holding::kCount);
}

TEST(RegisterMapJson, ReasonCodesAgree) {
  const nlohmann::json map = load_map();
  // The code's texts are human-readable ("slew limit out of range"), the JSON's identifiers
  // ("slew_out_of_range"): every word of the identifier must appear in the text, in order, so a
  // swapped pair of codes (illegal_address / illegal_function) fails.
  auto words = [](const std::string& s) {
    std::vector<std::string> out(1);
    for (const char ch : s) {
      if (ch == ' ' || ch == '_') out.emplace_back();
      else out.back() += ch;
    }
    return out;
  };
  ASSERT_EQ(map["reason_codes"].size(), std::size_t{kMaxReason} + 1);
  for (const auto& [code, name] : map["reason_codes"].items()) {
    const std::vector<std::string> text = words(to_string(static_cast<Reason>(std::stoi(code))));
    std::size_t at = 0;
    for (const std::string& word : words(name.get<std::string>())) {
      while (at < text.size() && text[at] != word) ++at;
      EXPECT_LT(at, text.size()) << "reason " << code << ": '" << word << "' of " << name << " not in order in '"
                                 << to_string(static_cast<Reason>(std::stoi(code))) << "'";
      ++at;
    }
    // The identifiers (the HTTP API's JSON) are the JSON's names exactly.
    EXPECT_EQ(identifier(static_cast<Reason>(std::stoi(code))), name.get<std::string>()) << "reason " << code;
  }
}

}  // namespace
}  // namespace swum::protocol::modbus
