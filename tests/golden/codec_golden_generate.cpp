// Writes tests/golden/codec_vectors.json: the representative inputs below, each run once on
// the current code (run_codec_case), input and output stored side by side.
//
//   cmake --build --preset ci --target swum_golden_codec_generate
//   build/ci/tests/golden/swum_golden_codec_generate tests/golden/codec_vectors.json
//
// Regenerating is ONLY for a deliberate change of a protocol (a register, scale, frame layout,
// code or client encoding that docs/protocols.md also changes), in a commit of its own that
// says which vectors changed and why; never to make a restructuring pass (README.md).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "codec_golden.h"

namespace {

using nlohmann::json;
using nlohmann::ordered_json;
using swum::golden::run_codec_case;

std::string hex16(unsigned v) {
  char b[8];
  std::snprintf(b, sizeof b, "%04x", v & 0xFFFFU);
  return b;
}
std::string hex8(unsigned v) {
  char b[4];
  std::snprintf(b, sizeof b, "%02x", v & 0xFFU);
  return b;
}
std::string read_pdu(unsigned fc, unsigned address, unsigned quantity) {
  return hex8(fc) + hex16(address) + hex16(quantity);
}
std::string write1(unsigned address, unsigned value) { return "06" + hex16(address) + hex16(value); }
std::string write_n(unsigned address, const std::vector<unsigned>& values) {
  std::string s = "10" + hex16(address) + hex16(static_cast<unsigned>(values.size())) +
                  hex8(2 * static_cast<unsigned>(values.size()));
  for (unsigned v : values) s += hex16(v);
  return s;
}
unsigned hi(std::uint32_t v) { return v >> 16; }
unsigned lo(std::uint32_t v) { return v & 0xFFFFU; }
unsigned i16(int v) { return static_cast<unsigned>(v) & 0xFFFFU; }

json setpoints(json f, json a, json p, json l, json fs, json as) {
  return {{"frequency_hz", f},
          {"amplitude_v", a},
          {"phase_deg", p},
          {"load_n", l},
          {"frequency_slew_hz_per_s", fs},
          {"amplitude_slew_v_per_s", as}};
}

json electrical(json ia, json ib, json pa, json pb, json ma, json mb, json wa, json wb) {
  return {{"current_a_a", ia},          {"current_b_a", ib},          {"phase_a_deg", pa}, {"phase_b_deg", pb},
          {"motional_phase_a_deg", ma}, {"motional_phase_b_deg", mb}, {"power_a_w", wa},   {"power_b_w", wb}};
}

// A telemetry snapshot with every field written out (defaults: a disabled amplifier at rest).
json telemetry(const json& overrides = json::object()) {
  json t = {{"tick", 0},
            {"sim_time_s", 0.0},
            {"state", 0},
            {"fault", 0},
            {"enable_line", true},
            {"at_setpoint", true},
            {"setpoints", setpoints(40000.0, 0.0, 90.0, 0.0, 1.0e6, 1.0e5)},
            {"output", {{"frequency_hz", 40000.0}, {"amplitude_v", 0.0}, {"phase_deg", 90.0}, {"load_n", 0.0}}},
            {"speed_m_s", 0.0},
            {"tick_speed_m_s", 0.0},
            {"position_m", 0.0},
            {"tip_normal_um", 0.0},
            {"tip_tangential_um", 0.0},
            {"applied_commands", 0},
            {"last_sequence", 0}};
  t.merge_patch(overrides);
  return t;
}

const json kDriving = telemetry(
    {{"tick", 123456},
     {"sim_time_s", 12.3456},
     {"state", 1},
     {"setpoints", setpoints(40123.456, 250.0, 90.0, 0.5, 1.0e6, 1.0e5)},
     {"output", {{"frequency_hz", 40123.4567}, {"amplitude_v", 250.0}, {"phase_deg", 90.0}, {"load_n", 0.5}}},
     {"speed_m_s", 0.2345678},
     {"tick_speed_m_s", 0.231},
     {"position_m", -0.0123456},
     {"tip_normal_um", 3.2105},
     {"tip_tangential_um", 2.4449},
     {"applied_commands", 42},
     {"last_sequence", 77},
     {"electrical", electrical(0.18346, 0.17912, 61.234, 58.765, -4.321, 3.219, 8.7654, 8.1234)},
     {"stator_temperature_c", 23.456}});
const json kFault = telemetry(
    {{"tick", 987654321},
     {"sim_time_s", 98765.4321},
     {"state", 2},
     {"fault", 2},
     {"enable_line", false},
     {"at_setpoint", false},
     {"setpoints", setpoints(39000.0, 300.0, -90.0, -1.25, 0.0, 0.0)},
     {"output", {{"frequency_hz", 39000.0}, {"amplitude_v", 300.0}, {"phase_deg", -90.0}, {"load_n", -1.25}}},
     {"speed_m_s", -0.5},
     {"tick_speed_m_s", -0.51234},
     {"position_m", -1.0},
     {"tip_normal_um", 0.0004},
     {"tip_tangential_um", 0.0005},
     {"applied_commands", 300},
     {"last_sequence", 1000}});
const json kTimeout = telemetry(
    {{"tick", 1000},
     {"sim_time_s", 0.1},
     {"state", 2},
     {"fault", 1},
     {"output", {{"frequency_hz", 40000.0}, {"amplitude_v", 0.0}, {"phase_deg", 90.0}, {"load_n", 0.0}}}});
const json kExtremes = telemetry(
    {{"tick", 4294967301ULL},  // 2^32 + 5
     {"sim_time_s", 5.0e6},
     {"state", 1},
     {"setpoints", setpoints(50000.0, 600.0, 180.0, 30.0, 1.0e7, 1.0e7)},
     {"output", {{"frequency_hz", 5.0e6}, {"amplitude_v", 7000.0}, {"phase_deg", -200.0}, {"load_n", -40.0}}},
     {"speed_m_s", 3000.0},
     {"tick_speed_m_s", -3000.0},
     {"position_m", -5000.0},
     {"tip_normal_um", 70.0},
     {"tip_tangential_um", 65.5355},
     {"applied_commands", 4294967297ULL},
     {"last_sequence", 8589934595ULL},
     {"electrical", electrical(7.0, -0.5, 400.0, -400.0, 180.0, -180.0, 500.0, -500.0)},
     {"stator_temperature_c", -400.0}});
const json kNonFinite = telemetry(
    {{"state", 1},
     {"sim_time_s", "nan"},
     {"output", {{"frequency_hz", "nan"}, {"amplitude_v", "inf"}, {"phase_deg", "nan"}, {"load_n", "-inf"}}},
     {"speed_m_s", "nan"},
     {"tick_speed_m_s", "inf"},
     {"position_m", "-inf"},
     {"tip_normal_um", "nan"},
     {"tip_tangential_um", "inf"},
     {"electrical", electrical("nan", "inf", "nan", "-inf", "inf", "nan", "-inf", "nan")},
     {"stator_temperature_c", "nan"}});
const json kEnabledIdle = telemetry(
    {{"tick", 7}, {"sim_time_s", 0.0007}, {"state", 1}, {"enable_line", false}, {"at_setpoint", false}});

class Vectors {
 public:
  void add(const std::string& kind, const std::string& name, const json& input) {
    ordered_json c;
    c["kind"] = kind;
    c["name"] = name;
    c["input"] = ordered_json::parse(input.dump());
    c["expect"] = ordered_json::parse(run_codec_case(kind, input).dump());
    cases_.push_back(c);
  }
  ordered_json document() const {
    ordered_json d;
    d["about"] = {
        "Golden codec vectors: today's Modbus register map, CAN frames and host client encodings, both directions.",
        "Generated once by tests/golden/codec_golden_generate.cpp from the code of the commit that added this file;",
        "checked by tests/golden/codec_golden_test.cpp. Regenerate ONLY for a deliberate protocol change (README.md).",
        "Frames: cansend notation ID#DATA (3 hex digits: 11-bit id); '/N' = DLC when it differs from the byte count.",
        "Modbus requests of host sessions: 'UNIT:PDU' in hex; exchanges: full Modbus TCP ADUs (MBAP + PDU) in hex.",
        "Reasons and exceptions are the wire codes of docs/protocols.md. Timing fields (lateness, compute time,",
        "overruns) are not captured: input registers 23-30 are null, the LoopStats frame is left out, inputs carry 0."};
    d["cases"] = cases_;
    return d;
  }

 private:
  ordered_json cases_ = ordered_json::array();
};

std::string frame_of(const json& encoded) { return encoded.at("frame").get<std::string>(); }

// Changes byte `index` of a frame "ID#HEX" with `edit`, then optionally re-seals the CRC of byte 7.
std::string edit_frame(const std::string& frame, std::size_t index, unsigned (*edit)(unsigned), bool reseal) {
  const auto hash = frame.find('#');
  std::string data = frame.substr(hash + 1);
  const unsigned byte = std::stoul(data.substr(2 * index, 2), nullptr, 16);
  data.replace(2 * index, 2, hex8(edit(byte)));
  if (reseal) {
    const unsigned id = std::stoul(frame.substr(0, hash), nullptr, 16);
    const json crc = run_codec_case("emu.can.crc8", {{"id", id}, {"data", data.substr(0, 14)}});
    data.replace(14, 2, hex8(crc.at("crc").get<unsigned>()));
  }
  return frame.substr(0, hash + 1) + data;
}

void modbus_cases(Vectors& v) {
  v.add("emu.codes", "reason, state and fault names", json::object());

  struct Pdu {
    const char* name;
    std::string pdu;
  };
  const std::uint32_t f1 = 40123456, f2 = 39500000, f_low = 29999999, f_high = 50000000, slew_high = 10000001;
  std::string q124 = "10" + hex16(0) + hex16(124) + hex8(248);
  for (int i = 0; i < 124; ++i) q124 += "0000";
  const std::vector<Pdu> pdus = {
      {"FC03 read all holding registers", read_pdu(0x03, 0, 10)},
      {"FC03 read the frequency (both words)", read_pdu(0x03, 1, 2)},
      {"FC04 read all input registers", read_pdu(0x04, 0, 35)},
      {"FC04 read status..sim time", read_pdu(0x04, 0, 23)},
      {"FC04 starts on the low word of speed", read_pdu(0x04, 9, 1)},
      {"FC04 ends on the high word of speed", read_pdu(0x04, 8, 1)},
      {"FC04 address 1000", read_pdu(0x04, 1000, 1)},
      {"FC03 address 500", read_pdu(0x03, 500, 2)},
      {"FC03 quantity 0", read_pdu(0x03, 0, 0)},
      {"FC04 quantity 126", read_pdu(0x04, 0, 126)},
      {"FC04 one byte too many", read_pdu(0x04, 0, 1) + "00"},
      {"FC03 one byte short", "03000000"},
      {"FC05 not supported", "050000ff00"},
      {"FC2B not supported", "2b0e0100"},
      {"empty PDU", ""},
      {"FC06 command keep-alive", write1(0, 0)},
      {"FC06 command enable", write1(0, 1)},
      {"FC06 command disable", write1(0, 2)},
      {"FC06 command reset fault", write1(0, 3)},
      {"FC06 command 4 unknown", write1(0, 4)},
      {"FC06 amplitude 250.0 V", write1(3, 2500)},
      {"FC06 amplitude 600.0 V (limit)", write1(3, 6000)},
      {"FC06 amplitude 600.1 V", write1(3, 6001)},
      {"FC06 phase -90.00 deg", write1(4, i16(-9000))},
      {"FC06 phase 180.00 deg (limit)", write1(4, 18000)},
      {"FC06 phase 180.01 deg", write1(4, 18001)},
      {"FC06 load -1.500 N", write1(5, i16(-1500))},
      {"FC06 load 30.001 N", write1(5, 30001)},
      {"FC06 load -30.001 N", write1(5, i16(-30001))},
      {"FC06 high word of the frequency alone", write1(1, 0)},
      {"FC06 low word of the frequency alone", write1(2, 0)},
      {"FC06 address 500", write1(500, 1)},
      {"FC06 one byte short", "06000000"},
      {"FC16 frequency 40123.456 Hz, 250.5 V, 90 deg, 0.25 N", write_n(1, {hi(f1), lo(f1), 2505, 9000, 250})},
      {"FC16 all holding registers",
       write_n(0, {1, hi(f2), lo(f2), 4000, i16(-4550), i16(-2000), hi(1000000), lo(1000000), hi(100000), lo(100000)})},
      {"FC16 enable + frequency + amplitude", write_n(0, {1, hi(f1), lo(f1), 4000})},
      {"FC16 frequency 29999.999 Hz", write_n(1, {hi(f_low), lo(f_low)})},
      {"FC16 frequency 50000.000 Hz (limit)", write_n(1, {hi(f_high), lo(f_high)})},
      {"FC16 slews 0 (unlimited)", write_n(6, {0, 0, 0, 0})},
      {"FC16 frequency slew 10000001 Hz/s", write_n(6, {hi(slew_high), lo(slew_high)})},
      {"FC16 amplitude slew 10000001 V/s", write_n(8, {hi(slew_high), lo(slew_high)})},
      {"FC16 low word of the frequency + amplitude", write_n(2, {0, 2500})},
      {"FC16 low word of frequency slew + high word of amplitude slew", write_n(7, {0, 0})},
      {"FC16 address 500", write_n(500, {1})},
      {"FC16 byte count does not match quantity", "10000300010400010002"},
      {"FC16 quantity 124", q124},
      {"FC06 advance 10 ticks (alone: a step, no command)", write1(10, 10)},
      {"FC16 set-points + advance 10 ticks (one request sets and steps)",
       write_n(1, {hi(f1), lo(f1), 2505, 9000, 250, hi(0), lo(0), hi(0), lo(0), 10})},
      {"FC03 read all holding registers with advance", read_pdu(0x03, 0, 11)},
      {"FC04 read all input registers with clock", read_pdu(0x04, 0, 36)},
      {"FC16 quantity 0", "1000000000"
                          "00"},
  };
  for (const auto& p : pdus) v.add("emu.modbus.request", p.name, {{"pdu", p.pdu}});

  v.add("emu.modbus.holding_registers", "typical", {{"setpoints", setpoints(40000.0, 250.0, 90.0, 0.0, 1.0e6, 1.0e5)}});
  v.add("emu.modbus.holding_registers", "rounding",
        {{"setpoints", setpoints(40123.4565, 123.45, -179.995, 0.0005, 1234.5, 0.4)}});
  v.add("emu.modbus.holding_registers", "negative and saturated",
        {{"setpoints", setpoints(-1.0, -5.0, 400.0, -40.0, 5.0e9, "nan")}});
  v.add("emu.modbus.holding_registers", "above the register range",
        {{"setpoints", setpoints(5.0e6, 7000.0, "nan", "inf", "inf", -1.0)}});

  const json no_rejects = {{"last", 0}, {"count", 0}};
  v.add("emu.modbus.input_registers", "disabled at rest", {{"telemetry", telemetry()}, {"rejects", no_rejects}});
  v.add("emu.modbus.input_registers", "enabled and driving",
        {{"telemetry", kDriving}, {"rejects", {{"last", 2}, {"count", 3}}}});
  v.add("emu.modbus.input_registers", "numerical fault, enable line low",
        {{"telemetry", kFault}, {"rejects", {{"last", 15}, {"count", 70000}}}});
  v.add("emu.modbus.input_registers", "watchdog fault",
        {{"telemetry", kTimeout}, {"rejects", {{"last", 12}, {"count", 1}}}});
  v.add("emu.modbus.input_registers", "saturation and wrap-around",
        {{"telemetry", kExtremes}, {"rejects", {{"last", 16}, {"count", 4294967303ULL}}}});
  v.add("emu.modbus.input_registers", "non-finite values", {{"telemetry", kNonFinite}, {"rejects", no_rejects}});
  v.add("emu.modbus.input_registers", "enabled without drive", {{"telemetry", kEnabledIdle}, {"rejects", no_rejects}});

  // The emulator's Modbus TCP server: one connection, requests in order (rejects are logged
  // and show in input registers 3-5 of later reads).
  auto req = [](const std::string& pdu, unsigned unit = 1) { return json{{"unit", unit}, {"pdu", pdu}}; };
  v.add("emu.modbus.exchange", "reads, writes and rejects on one connection",
        {{"telemetry", kDriving},
         {"requests",
          {req(read_pdu(0x03, 0, 10)), req(read_pdu(0x04, 0, 23)), req(read_pdu(0x04, 31, 4)),
           req(write_n(0, {1, hi(f1), lo(f1), 2505, 9000, 250})), req(write1(0, 0)), req(write1(3, 6001)),
           req(read_pdu(0x04, 0, 8)), req(read_pdu(0x04, 9, 1)), req(write1(0, 4)), req(read_pdu(0x04, 3, 3)),
           req("050000ff00"), req(read_pdu(0x04, 1000, 1)), req(write_n(6, {hi(1000000), lo(1000000), 0, 500})),
           req(read_pdu(0x04, 0, 8), 7), req(read_pdu(0x04, 0, 8))}}});
  v.add("emu.modbus.exchange", "fault snapshot",
        {{"telemetry", kFault}, {"requests", {req(read_pdu(0x04, 0, 23)), req(read_pdu(0x03, 0, 10))}}});

  for (const char* text :
       {"tcp://127.0.0.1:1502", "tcp://localhost:502", "tcp://0.0.0.0:0", "tcp://192.168.1.20:65535",
        "rtu:/dev/ttyUSB0:19200", "rtu:/dev/ttyS1", "udp://1.2.3.4:5", "tcp://127.0.0.1", "tcp://127.0.0.1:65536",
        "tcp://127.0.0.1:-1", "tcp://127.0.0.1:port", "rtu:/dev/ttyUSB0:0", ""})
    v.add("emu.modbus.endpoint", std::string("'") + text + "'", {{"text", text}});
}

struct Telemetries {
  const char* name;
  json telemetry;
  json rejects;
  unsigned counter;
  unsigned node;
};
const std::vector<Telemetries>& telemetry_sets() {
  static const std::vector<Telemetries> sets = {
      {"disabled at rest, node 1", telemetry(), {{"last", 0}, {"count", 0}}, 0, 1},
      {"enabled and driving, node 1", kDriving, {{"last", 2}, {"count", 3}}, 17, 1},
      {"numerical fault, node 42", kFault, {{"last", 15}, {"count", 70000}}, 255, 42},
      {"watchdog fault, node 127", kTimeout, {{"last", 12}, {"count", 1}}, 128, 127},
      {"saturation and wrap-around, node 1", kExtremes, {{"last", 16}, {"count", 4294967303ULL}}, 1, 1},
      {"non-finite values, node 1", kNonFinite, {{"last", 0}, {"count", 0}}, 2, 1},
      {"enabled without drive, node 3", kEnabledIdle, {{"last", 0}, {"count", 256}}, 3, 3},
  };
  return sets;
}

json encode_set(const Telemetries& s) {
  return run_codec_case("emu.can.telemetry_encode",
                        {{"node", s.node}, {"counter", s.counter}, {"telemetry", s.telemetry}, {"rejects", s.rejects}});
}

void can_cases(Vectors& v) {
  for (unsigned node : {1U, 42U, 127U}) v.add("emu.can.ids", "node " + std::to_string(node), {{"node", node}});

  v.add("emu.can.crc8", "id 0x201, zeros", {{"id", 0x201}, {"data", "00000000000000"}});
  v.add("emu.can.crc8", "id 0x301, 01..07", {{"id", 0x301}, {"data", "01020304050607"}});
  v.add("emu.can.crc8", "id 0x000, ones", {{"id", 0x000}, {"data", "ffffffffffffff"}});
  v.add("emu.can.crc8", "id 0x27F, ascii 1234567", {{"id", 0x27F}, {"data", "31323334353637"}});

  struct Cmd {
    const char* name;
    json in;
  };
  auto cmd = [](unsigned node, unsigned mode, unsigned alive, json f, json p, json a) {
    return json{{"node", node},      {"mode", mode},   {"alive", alive},
                {"frequency_hz", f}, {"phase_deg", p}, {"amplitude_v", a}};
  };
  const std::vector<Cmd> commands = {
      {"enable 40 kHz 90 deg 250 V", cmd(1, 1, 1, 40000.0, 90.0, 250.0)},
      {"disable, rounding", cmd(1, 0, 0, 39876.54, -90.05, 100.1)},
      {"reset fault, largest raw values, node 127", cmd(127, 2, 15, 104857.5, 204.7, 1023.75)},
      {"saturated high", cmd(42, 1, 7, 200000.0, -500.0, 2000.0)},
      {"negative and non-finite", cmd(1, 1, 8, -5.0, "nan", "nan")},
      {"mode 3 (rejected by the decoder)", cmd(5, 3, 3, 40000.0, 0.0, 0.0)},
      {"phase -180 deg, node 64", cmd(64, 1, 9, 39000.0, -180.0, 600.0)},
  };
  std::vector<std::string> encoded;
  for (const auto& c : commands) {
    v.add("emu.can.command_encode", c.name, c.in);
    encoded.push_back(frame_of(run_codec_case("emu.can.command_encode", c.in)));
  }
  for (std::size_t i = 0; i < encoded.size(); ++i)
    v.add("emu.can.command_decode", std::string(commands[i].name) + " (encoded above)", {{"frame", encoded[i]}});
  const std::string good = encoded[0];
  auto flip0 = [](unsigned b) { return b ^ 0x01U; };
  auto set_bit2 = [](unsigned b) { return b | 0x04U; };
  auto set_bit52 = [](unsigned b) { return b | 0x10U; };  // bit 52 = byte 6, bit 4
  v.add("emu.can.command_decode", "one payload bit flipped", {{"frame", edit_frame(good, 0, flip0, false)}});
  v.add("emu.can.command_decode", "CRC byte flipped", {{"frame", edit_frame(good, 7, flip0, false)}});
  v.add("emu.can.command_decode", "reserved bit 2 set, CRC valid", {{"frame", edit_frame(good, 0, set_bit2, true)}});
  v.add("emu.can.command_decode", "reserved bit 52 set, CRC valid", {{"frame", edit_frame(good, 6, set_bit52, true)}});
  v.add("emu.can.command_decode", "DLC 7", {{"frame", good.substr(0, good.size() - 2)}});
  v.add("emu.can.command_decode", "DLC 7 with 8 bytes in the buffer", {{"frame", good + "/7"}});
  v.add("emu.can.command_decode", "29-bit identifier", {{"frame", "00000" + good}});
  v.add("emu.can.command_decode", "node 1 payload under 0x202", {{"frame", "202" + good.substr(3)}});

  auto aux = [](unsigned node, unsigned alive, json load, json fs, json as) {
    return json{{"node", node},
                {"alive", alive},
                {"load_n", load},
                {"frequency_slew_hz_per_s", fs},
                {"amplitude_slew_v_per_s", as}};
  };
  const std::vector<Cmd> auxes = {
      {"load 0.5 N, 1 MHz/s, 100 kV/s", aux(1, 1, 0.5, 1.0e6, 1.0e5)},
      {"negative load, unlimited slews", aux(1, 2, -2.5, 0.0, 0.0)},
      {"largest raw values, node 127", aux(127, 15, 32.767, 6553500.0, 655350.0)},
      {"saturated", aux(42, 0, 40.0, 1.0e9, 1.0e9)},
      {"negative slews, rounding", aux(1, 3, -40.0, -100.0, -1.0)},
      {"half steps round", aux(1, 4, 0.0005, 150.0, 5.0)},
      {"non-finite", aux(1, 5, "nan", "inf", "nan")},
  };
  encoded.clear();
  for (const auto& c : auxes) {
    v.add("emu.can.aux_encode", c.name, c.in);
    encoded.push_back(frame_of(run_codec_case("emu.can.aux_encode", c.in)));
  }
  for (std::size_t i = 0; i < encoded.size(); ++i)
    v.add("emu.can.aux_decode", std::string(auxes[i].name) + " (encoded above)", {{"frame", encoded[i]}});
  const std::string good_aux = encoded[0];
  auto set_bit0 = [](unsigned b) { return b | 0x01U; };
  v.add("emu.can.aux_decode", "reserved bit 0 set, CRC valid", {{"frame", edit_frame(good_aux, 0, set_bit0, true)}});
  v.add("emu.can.aux_decode", "payload bit flipped", {{"frame", edit_frame(good_aux, 3, flip0, false)}});
  v.add("emu.can.aux_decode", "DLC 6", {{"frame", good_aux.substr(0, good_aux.size() - 4)}});

  auto steps = [](std::initializer_list<std::pair<unsigned, long long>> list) {
    json s = json::array();
    for (const auto& [alive, now] : list) s.push_back({{"alive", alive}, {"now_ns", now}});
    return json{{"steps", s}};
  };
  const long long ms = 1000000;
  v.add("emu.can.alive_counter", "ahead by 1..7 accepted, repeat and 8..15 stale, wrap",
        steps({{5, 0},
               {5, 1 * ms},
               {6, 2 * ms},
               {13, 3 * ms},
               {5, 4 * ms},
               {14, 5 * ms},
               {15, 6 * ms},
               {0, 7 * ms},
               {0, 8 * ms},
               {15, 9 * ms},
               {7, 10 * ms},
               {6, 11 * ms}}));
  v.add(
      "emu.can.alive_counter", "resynchronised after more than 1 s, not after exactly 1 s",
      steps(
          {{3, 0}, {3, 1000 * ms}, {3, 2000 * ms + 1}, {2, 2000 * ms + 2}, {10, 3000 * ms + 3}, {11, 3000 * ms + 4}}));
  v.add("emu.can.alive_counter", "first frame with any counter",
        steps({{0, 5 * ms}, {1, 6 * ms}, {9, 7 * ms}, {8, 8 * ms}}));

  for (const auto& s : telemetry_sets()) {
    v.add("emu.can.telemetry_encode", s.name,
          {{"node", s.node}, {"counter", s.counter}, {"telemetry", s.telemetry}, {"rejects", s.rejects}});
  }
  for (const auto& s : telemetry_sets()) {
    const json set = encode_set(s);
    for (const char* kind : {"status", "motion", "drive", "output", "clock"})
      v.add("emu.can.telemetry_decode", std::string(kind) + ": " + s.name, {{"as", kind}, {"frame", set.at(kind)}});
    for (const char* frame : {"electrical_a", "electrical_b"}) {
      v.add("emu.can.telemetry_decode", std::string(frame) + ": " + s.name,
            {{"as", "electrical"}, {"frame", set.at(frame)}});
    }
  }
  for (const char* kind : {"status", "motion", "drive", "output", "clock", "electrical"}) {
    v.add("emu.can.telemetry_decode", std::string(kind) + ": all bits set",
          {{"as", kind}, {"frame", "181#ffffffffffffffff"}});
    v.add("emu.can.telemetry_decode", std::string(kind) + ": DLC 7", {{"as", kind}, {"frame", "181#ffffffffffffff"}});
  }
  v.add("emu.can.telemetry_decode", "motion: 29-bit identifier",
        {{"as", "motion"}, {"frame", "00000281#0100000002000000"}});
}

// Input registers as a client reads them: the emulator's image of a telemetry snapshot, timing 0.
json served_registers(const json& t, const json& rejects) {
  json words = run_codec_case("emu.modbus.input_registers", {{"telemetry", t}, {"rejects", rejects}}).at("words");
  for (auto& w : words)
    if (w.is_null()) w = 0;
  return words;
}

json drive(json f, json amplitude_v, json phase, json load) {
  return {
      {"call", "set_drive"}, {"frequency_hz", f}, {"amplitude_v", amplitude_v}, {"phase_deg", phase}, {"load_n", load}};
}
json slew(json f, json amplitude_v) {
  return {{"call", "set_slew"}, {"frequency_hz_per_s", f}, {"amplitude_v_per_s", amplitude_v}};
}
json command(const char* action) { return {{"call", "command"}, {"action", action}}; }

void host_cases(Vectors& v) {
  json by_hand = json::array();
  for (int i = 0; i < 35; ++i) by_hand.push_back(0);
  by_hand[0] = 0x1F;  // every status bit
  by_hand[1] = 1;
  by_hand[2] = 0;
  by_hand[3] = 9;
  by_hand[4] = 0x0001;  // reject count 65536 + 2
  by_hand[5] = 0x0002;
  by_hand[8] = 0xFFFF;  // speed -1 um/s
  by_hand[9] = 0xFFFF;
  by_hand[10] = 0x8000;  // position INT32_MIN um
  by_hand[11] = 0x0000;
  by_hand[12] = 0xFFFF;
  by_hand[13] = 1;
  by_hand[14] = 0xFFFF;  // frequency 4294967.295 Hz
  by_hand[15] = 0xFFFF;
  by_hand[16] = 0xFFFF;
  by_hand[17] = 0xFFFF;  // phase -0.01 deg
  by_hand[18] = 0x8000;  // load -32.768 N
  by_hand[21] = 0xFFFF;  // sim time 4294967.295 s
  by_hand[22] = 0xFFFF;

  v.add("host.modbus.session", "setpoints, slews, commands",
        {{"calls",
          {drive(40123.456, 250.5, 90.0, 0.25), drive(39500.0, 0.0, -90.0, -1.5),
           drive(40000.0005, 123.45, -179.995, 0.0005), drive(40000.0, 7000.0, 90.0, 0.0),
           drive(40000.0, 100.0, 400.0, 0.0), drive(40000.0, 100.0, 90.0, -40.0), drive(-1.0, 100.0, 90.0, 0.0),
           drive(40000.0, "nan", 90.0, 0.0), slew(1.0e6, 1.0e5), slew(0.5, 0.0), slew(1234.9, 99.99), slew(-1.0, 0.0),
           slew(5.0e9, 0.0), command("keep_alive"), command("enable"), command("disable"), command("reset_fault")}}});
  v.add("host.modbus.session", "telemetry reads",
        {{"calls",
          {{{"call", "read"}, {"input_registers", served_registers(telemetry(), {{"last", 0}, {"count", 0}})}},
           {{"call", "read"}, {"input_registers", served_registers(kDriving, {{"last", 2}, {"count", 3}})}},
           {{"call", "read"}, {"input_registers", served_registers(kFault, {{"last", 15}, {"count", 70000}})}},
           {{"call", "read"}, {"input_registers", served_registers(kExtremes, {{"last", 16}, {"count", 7}})}},
           {{"call", "read"}, {"input_registers", by_hand}}}}});

  // CAN: telemetry sets as the emulator sends them (Status, Motion, Drive, LoopStats, Clock,
  // ElectricalA, ElectricalB, Output), the LoopStats payload zero.
  auto full_set = [](const Telemetries& s) {
    const json e = encode_set(s);
    char loop_stats[32];
    std::snprintf(loop_stats, sizeof loop_stats, "%03X#0000000000000000", 0x480U + s.node);
    return json::array({e.at("status"), e.at("motion"), e.at("drive"), std::string(loop_stats), e.at("clock"),
                        e.at("electrical_a"), e.at("electrical_b"), e.at("output")});
  };
  const auto& sets = telemetry_sets();
  const json rest = full_set(sets[0]);
  const json driving = full_set(sets[1]);
  const json extremes = full_set(sets[4]);
  json missing_drive = driving;
  missing_drive.erase(2);
  json short_status = driving;
  short_status[0] = short_status[0].get<std::string>().substr(0, 18);  // DLC 7
  json other_node = full_set(sets[2]);                                 // node 42
  json set_then_rest = missing_drive;  // an incomplete set is discarded, the next one returned
  for (const auto& f : extremes) set_then_rest.push_back(f);
  // A board without the electrical frames (the older protocol): the set is complete at Output,
  // the sample has no electrical values and no stator temperature; with one of the two, neither.
  json without_electrical = driving;
  without_electrical.erase(6);
  without_electrical.erase(5);
  json only_electrical_a = driving;
  only_electrical_a.erase(6);

  json calls = {drive(40000.0, 250.0, 90.0, 0.0),
                command("enable"),
                drive(39500.0, 300.0, -90.0, 1.5),
                slew(1.0e6, 1.0e5),
                slew(150.0, 5.0),
                slew(0.0, 0.0),
                slew(99.0, 9.99)};
  for (int i = 0; i < 13; ++i) calls.push_back(command("keep_alive"));  // the alive counter wraps
  for (const json& c : {command("disable"), command("reset_fault"), command("keep_alive"),
                        drive(39876.54, 100.1, -90.05, 1.5), drive(40000.0, 100.0, 90.0, -40.0)})
    calls.push_back(c);
  v.add("host.can.session", "commands, node 1", {{"node", 1}, {"connect_frames", rest}, {"calls", calls}});

  json node42 = full_set(sets[2]);
  v.add("host.can.session", "commands, node 42",
        {{"node", 42}, {"connect_frames", node42}, {"calls", {command("enable"), drive(41000.0, 50.0, 45.0, 0.0)}}});

  v.add("host.can.session", "telemetry reads, node 1",
        {{"node", 1},
         {"connect_frames", rest},
         {"calls",
          {{{"call", "read"}, {"frames", driving}},
           {{"call", "read"}, {"frames", extremes}},
           {{"call", "read"}, {"frames", set_then_rest}},
           {{"call", "read"}, {"frames", missing_drive}},
           {{"call", "read"}, {"frames", short_status}},
           {{"call", "read"}, {"frames", other_node}},
           {{"call", "read"}, {"frames", json::array()}},
           {{"call", "read"}, {"frames", full_set(sets[5])}},
           {{"call", "read"}, {"frames", without_electrical}},
           {{"call", "read"}, {"frames", only_electrical_a}}}}});
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: " << argv[0]
              << " OUT.json   (see tests/golden/README.md: only for a deliberate protocol change)\n";
    return 2;
  }
  Vectors v;
  modbus_cases(v);
  can_cases(v);
  host_cases(v);
  std::ofstream out(argv[1]);
  out << v.document().dump(1) << "\n";
  if (!out) {
    std::cerr << "cannot write " << argv[1] << "\n";
    return 1;
  }
  std::cout << "wrote " << v.document()["cases"].size() << " cases to " << argv[1] << "\n";
  return 0;
}
