// Runs golden codec cases on the current code (see codec_golden.h, tests/golden/README.md).
//
// Only the ADAPTER section below names the code under test (headers, namespaces, types,
// functions). A restructuring that moves or renames them updates that section (and, if struct
// fields are renamed, the converters right below it) — never codec_vectors.json.
#include "codec_golden.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <stdexcept>
#include <thread>
#include <utility>

// ============================== ADAPTER ==============================
// Wire codecs (protocol/ today) and the emulator (firmware_sim/):
#include "can_codec.h"  // ids_for_node, crc8, CommandFrame/AuxFrame encode/decode/to_command, AliveCounter, encode_<telemetry>
#include "can_telemetry_decode.h"      // decode_status/motion/drive/output/clock
#include "codes.h"                     // Reason, AmpState, FaultCode, Action, CommandSource, to_string()
#include "command.h"                   // Command, AmplifierLimits
#include "core/shared_state.h"         // SharedState
#include "endpoint.h"                  // parse_modbus_endpoint
#include "modbus_codec.h"              // parse_request, decide, fill_holding, fill_input, holding::/input:: addresses
#include "telemetry.h"                 // Telemetry, RejectSnapshot
#include "transports/modbus_server.h"  // ModbusTcpServer (the emulator's Modbus TCP framing)
// Host side (host/device/ and host/output/ today):
#include "device/can_device.h"     // CanDevice (CAN client: command/aux frames out, telemetry sets in)
#include "device/device.h"         // DeviceTelemetry, DriveSetpoint, DeviceAction, DeviceTimeouts, reject_reason_name
#include "device/modbus_device.h"  // ModbusDevice (Modbus client: register writes out, input registers in)
#include "output/log_table.h"      // format_log_row (one `swum log` CSV row)
// Frames (protocol/can_frame.h, carried by io/):
#include "can_bus.h"  // io::CanFrame, io::CanBus, io::CanFilter, io::CanResult, io::CanStatus

namespace swum::golden::adapter {
namespace emu = swum::emu;
namespace protocol = swum::protocol;
namespace mb = swum::protocol::modbus;
// The telemetry decoders report a Reason (the protocol's per-frame status); the captures
// record whether the frame decoded.
namespace can {
using namespace swum::protocol::can;
namespace wire = swum::protocol::can;
using Frame = swum::protocol::CanFrame;
constexpr auto kOk = swum::protocol::Reason::none;
inline bool decode_status(const Frame& f, StatusFields& o) { return wire::decode_status(f, o) == kOk; }
inline bool decode_motion(const Frame& f, MotionFields& o) { return wire::decode_motion(f, o) == kOk; }
inline bool decode_drive(const Frame& f, DriveFields& o) { return wire::decode_drive(f, o) == kOk; }
inline bool decode_output(const Frame& f, OutputFields& o) { return wire::decode_output(f, o) == kOk; }
inline bool decode_clock(const Frame& f, ClockFields& o) { return wire::decode_clock(f, o) == kOk; }
inline bool decode_electrical(const Frame& f, ElectricalFields& o) { return wire::decode_electrical(f, o) == kOk; }
}  // namespace can
namespace host = swum::host;
namespace io = swum::io;

using protocol::Command;
using protocol::Reason;
using protocol::Telemetry;
using Limits = protocol::AmplifierLimits;
using ModbusRequest = mb::Request;
using RejectSnapshot = protocol::RejectSnapshot;
using EmulatorShared = emu::SharedState;
using EmulatorModbusServer = emu::ModbusTcpServer;
using Endpoint = protocol::ModbusEndpoint;
constexpr std::size_t kHoldingCount = mb::holding::kCount;
constexpr std::size_t kInputCount = mb::input::kCount;
// Timing input registers (lateness, compute time, overruns): not reproducible, never captured.
constexpr std::uint16_t kTimingFirst = mb::input::kLatenessP50;
constexpr std::uint16_t kTimingLast = mb::input::kOverruns + 1;  // low word of the u32

inline std::uint8_t parse_request(std::span<const std::uint8_t> pdu, ModbusRequest& r, Reason* why) {
  return mb::parse_request(pdu, r, why);
}
inline mb::Decision decide(const ModbusRequest& r, const Limits& limits) { return mb::decide(r, limits); }
inline void fill_holding(const Telemetry& t, std::span<std::uint16_t, kHoldingCount> r) { mb::fill_holding(t, r); }
inline void fill_input(const Telemetry& t, const RejectSnapshot& s, std::span<std::uint16_t, kInputCount> r) {
  mb::fill_input(t, s, r);
}
inline std::string parse_endpoint(const std::string& text, Endpoint& out) {
  return protocol::parse_modbus_endpoint(text, out);
}
inline const char* reason_name(Reason r) { return protocol::to_string(r); }
inline const char* state_name(protocol::AmpState s) { return protocol::to_string(s); }
inline const char* fault_name(protocol::FaultCode f) { return protocol::to_string(f); }
inline std::string host_reject_name(int code) { return host::reject_reason_name(code); }
inline std::string log_row(double host_s, const host::DeviceTelemetry& t) { return host::format_log_row(host_s, t); }
}  // namespace swum::golden::adapter
// ============================ END ADAPTER ============================

namespace swum::golden {
namespace {

namespace a = adapter;
using nlohmann::json;

// ---------------------------------------------------------------- helpers
std::vector<std::uint8_t> from_hex(const std::string& text) {
  if (text.size() % 2 != 0) throw std::invalid_argument("odd hex string '" + text + "'");
  std::vector<std::uint8_t> bytes;
  for (std::size_t i = 0; i < text.size(); i += 2)
    bytes.push_back(static_cast<std::uint8_t>(std::stoul(text.substr(i, 2), nullptr, 16)));
  return bytes;
}
std::string to_hex(std::span<const std::uint8_t> bytes) {
  std::string text;
  char b[3];
  for (std::uint8_t x : bytes) {
    std::snprintf(b, sizeof b, "%02x", x);
    text += b;
  }
  return text;
}

// Inputs may spell non-finite numbers as strings.
double num(const json& j) {
  if (j.is_string()) {
    const std::string s = j.get<std::string>();
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
    throw std::invalid_argument("not a number: " + s);
  }
  return j.get<double>();
}

// Frames in can-utils' cansend notation: "201#0011223344556677" (3 hex digits: 11-bit id,
// 8: 29-bit); the number of data bytes is the DLC. A frame whose DLC differs from its byte
// count (a wrong-length frame) is written "201#0011223344556677/7".
std::string frame_text(const a::io::CanFrame& f) {
  char id[16];
  std::snprintf(id, sizeof id, f.extended ? "%08X" : "%03X", f.id);
  const std::size_t shown = std::min<std::size_t>(f.dlc, 8);
  return std::string(id) + "#" + to_hex(std::span<const std::uint8_t>(f.data.data(), shown));
}
a::io::CanFrame frame_from(const std::string& text) {
  const auto hash = text.find('#');
  if (hash == std::string::npos) throw std::invalid_argument("not a frame: " + text);
  a::io::CanFrame f;
  const std::string id = text.substr(0, hash);
  f.extended = id.size() == 8;
  f.id = static_cast<std::uint32_t>(std::stoul(id, nullptr, 16));
  std::string data = text.substr(hash + 1);
  int dlc = -1;
  if (const auto slash = data.find('/'); slash != std::string::npos) {
    dlc = std::stoi(data.substr(slash + 1));
    data = data.substr(0, slash);
  }
  const auto bytes = from_hex(data);
  if (bytes.size() > 8) throw std::invalid_argument("more than 8 data bytes: " + text);
  std::copy(bytes.begin(), bytes.end(), f.data.begin());
  f.dlc = static_cast<std::uint8_t>(dlc >= 0 ? dlc : static_cast<int>(bytes.size()));
  return f;
}
std::string hex_id(std::uint32_t id) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%03X", id);
  return b;
}

// ---------------------------------------------------------------- converters (field names)
a::Limits limits_from(const json& j) {
  a::Limits l;
  l.min_frequency_hz = num(j.at("min_frequency_hz"));
  l.max_frequency_hz = num(j.at("max_frequency_hz"));
  l.max_amplitude_v = num(j.at("max_amplitude_v"));
  l.max_abs_phase_deg = num(j.at("max_abs_phase_deg"));
  l.max_abs_load_n = num(j.at("max_abs_load_n"));
  l.max_frequency_slew_hz_per_s = num(j.at("max_frequency_slew_hz_per_s"));
  l.max_amplitude_slew_v_per_s = num(j.at("max_amplitude_slew_v_per_s"));
  return l;
}

void set_setpoints(a::Telemetry& t, const json& s) {
  t.setpoints.frequency_hz = num(s.at("frequency_hz"));
  t.setpoints.amplitude_v = num(s.at("amplitude_v"));
  t.setpoints.phase_deg = num(s.at("phase_deg"));
  t.setpoints.load_n = num(s.at("load_n"));
  t.setpoints.frequency_slew_hz_per_s = num(s.at("frequency_slew_hz_per_s"));
  t.setpoints.amplitude_slew_v_per_s = num(s.at("amplitude_slew_v_per_s"));
}

a::Telemetry telemetry_from(const json& j) {
  a::Telemetry t;  // loop statistics stay zero: timing is not captured
  t.tick = j.at("tick").get<std::uint64_t>();
  t.sim_time_s = num(j.at("sim_time_s"));
  t.state = static_cast<a::emu::AmpState>(j.at("state").get<int>());
  t.fault = static_cast<a::emu::FaultCode>(j.at("fault").get<int>());
  t.enable_line = j.at("enable_line").get<bool>();
  t.at_setpoint = j.at("at_setpoint").get<bool>();
  set_setpoints(t, j.at("setpoints"));
  const json& o = j.at("output");
  t.output.frequency_hz = num(o.at("frequency_hz"));
  t.output.amplitude_v = num(o.at("amplitude_v"));
  t.output.phase_deg = num(o.at("phase_deg"));
  t.output.load_n = num(o.at("load_n"));
  t.speed_m_s = num(j.at("speed_m_s"));
  t.tick_speed_m_s = num(j.at("tick_speed_m_s"));
  t.position_m = num(j.at("position_m"));
  t.tip_normal_um = num(j.at("tip_normal_um"));
  t.tip_tangential_um = num(j.at("tip_tangential_um"));
  t.applied_commands = j.at("applied_commands").get<std::uint64_t>();
  t.last_sequence = j.at("last_sequence").get<std::uint64_t>();
  // The electrical port (issue: electrical registers and frames); absent: the defaults.
  if (j.contains("electrical")) {
    const json& e = j.at("electrical");
    t.electrical.current_a_a = num(e.at("current_a_a"));
    t.electrical.current_b_a = num(e.at("current_b_a"));
    t.electrical.phase_a_deg = num(e.at("phase_a_deg"));
    t.electrical.phase_b_deg = num(e.at("phase_b_deg"));
    t.electrical.motional_phase_a_deg = num(e.at("motional_phase_a_deg"));
    t.electrical.motional_phase_b_deg = num(e.at("motional_phase_b_deg"));
    t.electrical.power_a_w = num(e.at("power_a_w"));
    t.electrical.power_b_w = num(e.at("power_b_w"));
  }
  if (j.contains("stator_temperature_c")) t.stator_temperature_c = num(j.at("stator_temperature_c"));
  return t;
}

a::RejectSnapshot rejects_from(const json& j) {
  a::RejectSnapshot r;
  r.last = static_cast<a::Reason>(j.at("last").get<int>());
  r.count = j.at("count").get<std::uint64_t>();
  return r;
}

const char* action_name(a::emu::Action action) {
  switch (action) {
    case a::emu::Action::none: return "none";
    case a::emu::Action::enable: return "enable";
    case a::emu::Action::disable: return "disable";
    case a::emu::Action::reset_fault: return "reset_fault";
  }
  return "?";
}
const char* source_name(a::emu::CommandSource source) {
  switch (source) {
    case a::emu::CommandSource::modbus: return "modbus";
    case a::emu::CommandSource::can: return "can";
    case a::emu::CommandSource::internal: return "internal";
  }
  return "?";
}

// Only the fields the command sets (a partial command changes only those).
json command_json(const a::Command& c) {
  json j;
  j["source"] = source_name(c.source);
  json set = json::object();
  if (c.fields & a::Command::kAction) set["action"] = action_name(c.action);
  if (c.fields & a::Command::kFrequency) set["frequency_hz"] = c.frequency_hz;
  if (c.fields & a::Command::kAmplitude) set["amplitude_v"] = c.amplitude_v;
  if (c.fields & a::Command::kPhase) set["phase_deg"] = c.phase_deg;
  if (c.fields & a::Command::kLoad) set["load_n"] = c.load_n;
  if (c.fields & a::Command::kFrequencySlew) set["frequency_slew_hz_per_s"] = c.frequency_slew_hz_per_s;
  if (c.fields & a::Command::kAmplitudeSlew) set["amplitude_slew_v_per_s"] = c.amplitude_slew_v_per_s;
  j["set"] = set;
  return j;
}

json device_telemetry_json(const a::host::DeviceTelemetry& t) {
  json j;
  j["device_time_s"] = t.device_time_s ? json(*t.device_time_s) : json(nullptr);
  j["sample_counter"] = t.sample_counter ? json(*t.sample_counter) : json(nullptr);
  j["sample_counter_modulus"] = t.sample_counter_modulus;
  j["state"] = t.state;
  j["fault_code"] = t.fault_code;
  j["drive_on"] = t.drive_on;
  j["enable_line"] = t.enable_line;
  j["last_reject"] = t.last_reject;
  j["reject_count"] = t.reject_count;
  j["reject_count_modulus"] = t.reject_count_modulus;
  j["speed_mm_s"] = t.speed_mm_s;
  j["position_mm"] = t.position_mm;
  j["tip_normal_um"] = t.tip_normal_um;
  j["tip_tangential_um"] = t.tip_tangential_um;
  j["frequency_hz"] = t.frequency_hz;
  j["amplitude_v"] = t.amplitude_v;
  j["phase_deg"] = t.phase_deg;
  j["load_n"] = t.load_n;
  if (t.electrical) {
    const auto& e = *t.electrical;
    j["electrical"] = {{"current_a_a", e.current_a_a},
                       {"current_b_a", e.current_b_a},
                       {"phase_a_deg", e.phase_a_deg},
                       {"phase_b_deg", e.phase_b_deg},
                       {"motional_phase_a_deg", e.motional_phase_a_deg},
                       {"motional_phase_b_deg", e.motional_phase_b_deg},
                       {"power_a_w", e.power_a_w},
                       {"power_b_w", e.power_b_w}};
  } else {
    j["electrical"] = nullptr;
  }
  j["stator_temperature_c"] = t.stator_temperature_c ? json(*t.stator_temperature_c) : json(nullptr);
  // lateness_p99_us, lateness_max_us, overruns: timing, not captured (the inputs carry zeros).
  return j;
}

a::host::DriveSetpoint setpoint_from(const json& j) {
  a::host::DriveSetpoint s;
  s.frequency_hz = num(j.at("frequency_hz"));
  s.amplitude_v = num(j.at("amplitude_v"));
  s.phase_deg = num(j.at("phase_deg"));
  s.load_n = num(j.at("load_n"));
  return s;
}
a::host::DeviceAction action_from(const std::string& name) {
  if (name == "keep_alive") return a::host::DeviceAction::keep_alive;
  if (name == "enable") return a::host::DeviceAction::enable;
  if (name == "disable") return a::host::DeviceAction::disable;
  if (name == "reset_fault") return a::host::DeviceAction::reset_fault;
  throw std::invalid_argument("unknown action " + name);
}

// The limits every Modbus case is decided with (swum-emu's defaults today, written out).
a::Limits modbus_limits() {
  return limits_from(json{{"min_frequency_hz", 30000.0},
                          {"max_frequency_hz", 50000.0},
                          {"max_amplitude_v", 600.0},
                          {"max_abs_phase_deg", 180.0},
                          {"max_abs_load_n", 30.0},
                          {"max_frequency_slew_hz_per_s", 1.0e7},
                          {"max_amplitude_slew_v_per_s", 1.0e7}});
}

json input_words_json(std::span<const std::uint16_t> r) {
  json words = json::array();
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (i >= a::kTimingFirst && i <= a::kTimingLast) words.push_back(nullptr);
    else words.push_back(r[i]);
  }
  return words;
}

// ---------------------------------------------------------------- emulator: Modbus
json modbus_request(const json& in) {
  const auto pdu = from_hex(in.at("pdu").get<std::string>());
  a::ModbusRequest request;
  a::Reason why = a::Reason::none;
  json out;
  std::uint8_t exception = a::parse_request(pdu, request, &why);
  out["command"] = nullptr;
  if (exception == 0) {
    const auto d = a::decide(request, modbus_limits());
    exception = d.exception;
    why = d.reason;
    if (d.has_command) out["command"] = command_json(d.command);
    if (d.advance_ticks != 0) out["advance_ticks"] = d.advance_ticks;  // issue 13: lockstep step
  }
  out["exception"] = exception;
  out["reason"] = static_cast<int>(why);
  return out;
}

// Holding registers hold only set-points: the rest of the snapshot does not reach them.
json modbus_holding(const json& in) {
  a::Telemetry t;
  set_setpoints(t, in.at("setpoints"));
  std::array<std::uint16_t, a::kHoldingCount> r{};
  r.fill(0xBEEF);  // every register must be written
  a::fill_holding(t, r);
  return {{"words", r}};
}

json modbus_input(const json& in) {
  std::array<std::uint16_t, a::kInputCount> r{};
  r.fill(0xBEEF);
  a::fill_input(telemetry_from(in.at("telemetry")), rejects_from(in.at("rejects")), r);
  return {{"words", input_words_json(r)}};
}

json modbus_endpoint(const json& in) {
  a::Endpoint e;
  const std::string problem = a::parse_endpoint(in.at("text").get<std::string>(), e);
  if (!problem.empty()) return {{"ok", false}};
  if (e.tcp) return {{"ok", true}, {"tcp", true}, {"host", e.host}, {"port", e.port}};
  return {{"ok", true}, {"tcp", false}, {"device", e.device}, {"baud", e.baud}};
}

// A socket helper for the in-process TCP exchanges.
bool read_exactly(int fd, std::uint8_t* data, std::size_t n, int timeout_ms) {
  std::size_t got = 0;
  while (got < n) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, timeout_ms) <= 0) return false;
    const ssize_t r = ::recv(fd, data + got, n - got, 0);
    if (r <= 0) return false;
    got += static_cast<std::size_t>(r);
  }
  return true;
}
bool write_all(int fd, const std::vector<std::uint8_t>& data) {
  std::size_t sent = 0;
  while (sent < data.size()) {
    const ssize_t r = ::send(fd, data.data() + sent, data.size() - sent, MSG_NOSIGNAL);
    if (r <= 0) return false;
    sent += static_cast<std::size_t>(r);
  }
  return true;
}
int connect_loopback(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::runtime_error("socket failed");
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    throw std::runtime_error("connect to 127.0.0.1:" + std::to_string(port) + " failed");
  }
  return fd;
}

// The emulator's Modbus TCP server (framing, exceptions, command queue, reject log) with a fixed
// telemetry snapshot and no loop: request ADUs in, response ADUs and queued commands out.
json modbus_exchange(const json& in) {
  a::EmulatorShared shared;
  shared.telemetry.store(telemetry_from(in.at("telemetry")));
  a::EmulatorModbusServer server("127.0.0.1", 0, shared, modbus_limits());
  server.start();
  const int fd = connect_loopback(server.port());
  json responses = json::array();
  std::uint16_t transaction = 0;
  for (const json& request : in.at("requests")) {
    const auto pdu = from_hex(request.at("pdu").get<std::string>());
    const auto unit = request.at("unit").get<std::uint8_t>();
    ++transaction;
    const auto length = static_cast<std::uint16_t>(pdu.size() + 1);
    std::vector<std::uint8_t> adu{
        static_cast<std::uint8_t>(transaction >> 8), static_cast<std::uint8_t>(transaction & 0xFF), 0,   0,
        static_cast<std::uint8_t>(length >> 8),      static_cast<std::uint8_t>(length & 0xFF),      unit};
    adu.insert(adu.end(), pdu.begin(), pdu.end());
    std::string answer;
    std::uint8_t header[7];
    if (write_all(fd, adu) && read_exactly(fd, header, 7, 5000)) {
      const std::size_t rest = static_cast<std::size_t>((header[4] << 8) | header[5]) - 1;
      std::vector<std::uint8_t> body(rest);
      if (rest < 260 && read_exactly(fd, body.data(), rest, 5000)) {
        answer = to_hex(header) + to_hex(body);
      }
    }
    responses.push_back(answer.empty() ? json(nullptr) : json(answer));
  }
  ::close(fd);
  server.stop();
  json commands = json::array();
  a::Command c;
  while (shared.commands.try_pop(c)) {
    json j = command_json(c);
    j["sequence"] = c.sequence;
    commands.push_back(j);
  }
  return {{"responses", responses},
          {"commands", commands},
          {"reject_count", shared.rejects.count.load()},
          {"last_reject", shared.rejects.last_reason.load()}};
}

json codes(const json&) {
  json reasons = json::array(), states = json::array(), faults = json::array(), host_names = json::array();
  for (int i = 0; i <= 17; ++i) reasons.push_back(a::reason_name(static_cast<a::Reason>(i)));
  for (int i = 0; i <= 3; ++i) states.push_back(a::state_name(static_cast<a::emu::AmpState>(i)));
  for (int i = 0; i <= 3; ++i) faults.push_back(a::fault_name(static_cast<a::emu::FaultCode>(i)));
  for (int i = -1; i <= 18; ++i) host_names.push_back(a::host_reject_name(i));
  return {{"reasons_0_17", reasons},
          {"states_0_3", states},
          {"faults_0_3", faults},
          {"host_reject_names_m1_18", host_names}};
}

// ---------------------------------------------------------------- emulator: CAN
json can_ids(const json& in) {
  const auto ids = a::can::ids_for_node(in.at("node").get<std::uint8_t>());
  return {{"command", hex_id(ids.command)},
          {"aux", hex_id(ids.aux)},
          {"status", hex_id(ids.status)},
          {"motion", hex_id(ids.motion)},
          {"drive", hex_id(ids.drive)},
          {"loop_stats", hex_id(ids.loop_stats)},
          {"output", hex_id(ids.output)},
          {"clock", hex_id(ids.clock)},
          {"heartbeat", hex_id(ids.heartbeat)},
          {"electrical_a", hex_id(ids.electrical_a)},
          {"electrical_b", hex_id(ids.electrical_b)}};
}

json can_crc8(const json& in) {
  const auto data = from_hex(in.at("data").get<std::string>());
  return {{"crc", a::can::crc8(in.at("id").get<std::uint32_t>(), data.data(), data.size())}};
}

json can_command_encode(const json& in) {
  a::can::CommandFrame c;
  c.mode = in.at("mode").get<std::uint8_t>();
  c.alive = in.at("alive").get<std::uint8_t>();
  c.frequency_hz = num(in.at("frequency_hz"));
  c.phase_deg = num(in.at("phase_deg"));
  c.amplitude_v = num(in.at("amplitude_v"));
  const auto ids = a::can::ids_for_node(in.at("node").get<std::uint8_t>());
  return {{"frame", frame_text(a::can::encode_command(c, ids.command))}};
}

json can_command_decode(const json& in) {
  a::can::CommandFrame c;
  const a::Reason why = a::can::decode_command(frame_from(in.at("frame").get<std::string>()), c);
  json out{{"reason", static_cast<int>(why)}};
  if (why == a::Reason::none) {
    out["mode"] = c.mode;
    out["alive"] = c.alive;
    out["frequency_hz"] = c.frequency_hz;
    out["phase_deg"] = c.phase_deg;
    out["amplitude_v"] = c.amplitude_v;
    out["command"] = command_json(a::can::to_command(c));
  }
  return out;
}

json can_aux_encode(const json& in) {
  a::can::AuxFrame x;
  x.alive = in.at("alive").get<std::uint8_t>();
  x.load_n = num(in.at("load_n"));
  x.frequency_slew_hz_per_s = num(in.at("frequency_slew_hz_per_s"));
  x.amplitude_slew_v_per_s = num(in.at("amplitude_slew_v_per_s"));
  const auto ids = a::can::ids_for_node(in.at("node").get<std::uint8_t>());
  return {{"frame", frame_text(a::can::encode_aux(x, ids.aux))}};
}

json can_aux_decode(const json& in) {
  a::can::AuxFrame x;
  const a::Reason why = a::can::decode_aux(frame_from(in.at("frame").get<std::string>()), x);
  json out{{"reason", static_cast<int>(why)}};
  if (why == a::Reason::none) {
    out["alive"] = x.alive;
    out["load_n"] = x.load_n;
    out["frequency_slew_hz_per_s"] = x.frequency_slew_hz_per_s;
    out["amplitude_slew_v_per_s"] = x.amplitude_slew_v_per_s;
    out["command"] = command_json(a::can::to_command(x));
  }
  return out;
}

// Each step: check the counter at a time; accept it when the check passes (as the transport does).
json can_alive(const json& in) {
  a::can::AliveCounter counter;
  json reasons = json::array();
  for (const json& step : in.at("steps")) {
    const auto alive = step.at("alive").get<std::uint8_t>();
    const auto now = step.at("now_ns").get<std::int64_t>();
    const a::Reason why = counter.check(alive, now);
    if (why == a::Reason::none) counter.accept(alive, now);
    reasons.push_back(static_cast<int>(why));
  }
  return {{"reasons", reasons}};
}

json can_telemetry_encode(const json& in) {
  const a::Telemetry t = telemetry_from(in.at("telemetry"));
  const auto ids = a::can::ids_for_node(in.at("node").get<std::uint8_t>());
  // LoopStats (0x480+N) is all timing: not captured. Output's last two bytes (lateness p50)
  // carry the zero statistics of the input.
  return {{"status", frame_text(a::can::encode_status(t, rejects_from(in.at("rejects")),
                                                      in.at("counter").get<std::uint8_t>(), ids.status))},
          {"motion", frame_text(a::can::encode_motion(t, ids.motion))},
          {"drive", frame_text(a::can::encode_drive(t, ids.drive))},
          {"output", frame_text(a::can::encode_output(t, ids.output))},
          {"clock", frame_text(a::can::encode_clock(t, ids.clock))},
          {"electrical_a", frame_text(a::can::encode_electrical_a(t, ids.electrical_a))},
          {"electrical_b", frame_text(a::can::encode_electrical_b(t, ids.electrical_b))},
          {"heartbeat", frame_text(a::can::encode_heartbeat(ids.heartbeat))}};
}

json can_telemetry_decode(const json& in) {
  const auto f = frame_from(in.at("frame").get<std::string>());
  const std::string as = in.at("as").get<std::string>();
  json out;
  bool ok = false;
  if (as == "status") {
    a::can::StatusFields s;
    ok = a::can::decode_status(f, s);
    if (ok)
      out = {{"state", s.state},
             {"enable_line", s.enable_line},
             {"drive_on", s.drive_on},
             {"at_setpoint", s.at_setpoint},
             {"fault", s.fault},
             {"last_reject", s.last_reject},
             {"reject_count", s.reject_count},
             {"applied_count", s.applied_count},
             {"status_counter", s.status_counter},
             {"stator_temperature_c", s.stator_temperature_c}};
  } else if (as == "motion") {
    a::can::MotionFields m;
    ok = a::can::decode_motion(f, m);
    if (ok) out = {{"speed_mm_s", m.speed_mm_s}, {"position_mm", m.position_mm}};
  } else if (as == "drive") {
    a::can::DriveFields d;
    ok = a::can::decode_drive(f, d);
    if (ok)
      out = {{"tip_normal_um", d.tip_normal_um},
             {"tip_tangential_um", d.tip_tangential_um},
             {"amplitude_v", d.amplitude_v},
             {"phase_deg", d.phase_deg}};
  } else if (as == "output") {
    a::can::OutputFields o;
    ok = a::can::decode_output(f, o);
    if (ok) out = {{"frequency_hz", o.frequency_hz}, {"load_n", o.load_n}};  // lateness p50: timing
  } else if (as == "clock") {
    a::can::ClockFields c;
    ok = a::can::decode_clock(f, c);
    if (ok) out = {{"sim_time_s", c.sim_time_s}, {"tick", c.tick}};
  } else if (as == "electrical") {
    a::can::ElectricalFields e;
    ok = a::can::decode_electrical(f, e);
    if (ok)
      out = {{"current_a", e.current_a},
             {"phase_deg", e.phase_deg},
             {"motional_phase_deg", e.motional_phase_deg},
             {"power_w", e.power_w}};
  } else {
    throw std::invalid_argument("unknown telemetry frame kind " + as);
  }
  if (!ok) out = json::object();
  out["ok"] = ok;
  return out;
}

// ---------------------------------------------------------------- host: Modbus client
// The calls of a session on either client: set_drive, set_slew, command, read. `before_read`
// puts the answer on the line; `record` adds what went over it to the call's result.
json run_calls(a::host::Device& device, const json& calls, const std::function<void(const json&)>& before_read,
               const std::function<void(json&)>& record) {
  json results = json::array();
  for (const json& call : calls) {
    const std::string what = call.at("call").get<std::string>();
    json result;
    try {
      if (what == "set_drive") {
        device.set_drive(setpoint_from(call));
      } else if (what == "set_slew") {
        device.set_slew(num(call.at("frequency_hz_per_s")), num(call.at("amplitude_v_per_s")));
      } else if (what == "command") {
        device.command(action_from(call.at("action").get<std::string>()));
      } else if (what == "read") {
        before_read(call);
        const auto t = device.read();
        result["telemetry"] = device_telemetry_json(t);
        result["log_row"] = a::log_row(1.25, t);
      } else {
        throw std::invalid_argument("unknown call " + what);
      }
    } catch (const a::host::DeviceError&) {
      result["error"] = true;
    }
    record(result);
    results.push_back(result);
  }
  return results;
}

// A Modbus TCP slave on 127.0.0.1 that records every request (unit id + PDU) and answers reads
// from a register image the case sets, writes with the standard echo.
class RecordingSlave {
 public:
  RecordingSlave() {
    listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof addr;
    if (listen_fd_ < 0 || ::bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        ::listen(listen_fd_, 1) != 0 || ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
      throw std::runtime_error("recording slave: cannot listen");
    port_ = ntohs(addr.sin_port);
    thread_ = std::thread([this] { run(); });
  }
  ~RecordingSlave() {
    stop_ = true;
    thread_.join();
    ::close(listen_fd_);
  }
  std::uint16_t port() const { return port_; }
  void set_registers(std::vector<std::uint16_t> r) {
    std::lock_guard lock(mutex_);
    registers_ = std::move(r);
  }
  std::vector<std::string> take_requests() {
    std::lock_guard lock(mutex_);
    return std::exchange(requests_, {});
  }

 private:
  void run() {
    int fd = -1;
    while (!stop_ && fd < 0) {
      pollfd p{listen_fd_, POLLIN, 0};
      if (::poll(&p, 1, 20) > 0) fd = ::accept(listen_fd_, nullptr, nullptr);
    }
    while (!stop_ && fd >= 0) {
      std::uint8_t h[7];
      pollfd p{fd, POLLIN, 0};
      if (::poll(&p, 1, 20) <= 0) continue;
      if (!read_exactly(fd, h, 7, 2000)) break;
      const std::size_t n = static_cast<std::size_t>((h[4] << 8) | h[5]) - 1;
      std::vector<std::uint8_t> pdu(n);
      if (n == 0 || n > 253 || !read_exactly(fd, pdu.data(), n, 2000)) break;
      std::vector<std::uint8_t> reply;
      {
        std::lock_guard lock(mutex_);
        requests_.push_back(to_hex(std::span<const std::uint8_t>(&h[6], 1)) + ":" + to_hex(pdu));
        const std::uint8_t fc = pdu[0];
        if ((fc == 0x03 || fc == 0x04) && n == 5) {
          const unsigned address = (pdu[1] << 8) | pdu[2], quantity = (pdu[3] << 8) | pdu[4];
          reply = {fc, static_cast<std::uint8_t>(2 * quantity)};
          for (unsigned i = 0; i < quantity; ++i) {
            const std::uint16_t w = address + i < registers_.size() ? registers_[address + i] : 0;
            reply.push_back(static_cast<std::uint8_t>(w >> 8));
            reply.push_back(static_cast<std::uint8_t>(w & 0xFF));
          }
        } else if (fc == 0x10 && n >= 5) {
          reply.assign(pdu.begin(), pdu.begin() + 5);
        } else if (fc == 0x06 && n == 5) {
          reply = pdu;
        } else {
          reply = {static_cast<std::uint8_t>(fc | 0x80), 0x01};
        }
      }
      const auto length = static_cast<std::uint16_t>(reply.size() + 1);
      std::vector<std::uint8_t> adu{
          h[0], h[1], h[2], h[3], static_cast<std::uint8_t>(length >> 8), static_cast<std::uint8_t>(length & 0xFF),
          h[6]};
      adu.insert(adu.end(), reply.begin(), reply.end());
      if (!write_all(fd, adu)) break;
    }
    if (fd >= 0) ::close(fd);
  }
  int listen_fd_ = -1;
  std::uint16_t port_ = 0;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::vector<std::uint16_t> registers_;
  std::vector<std::string> requests_;
  std::thread thread_;
};

std::vector<std::uint16_t> words_from(const json& j) {
  std::vector<std::uint16_t> w;
  for (const json& x : j) w.push_back(x.get<std::uint16_t>());
  return w;
}

json host_modbus_session(const json& in) {
  RecordingSlave slave;  // answers the connect-time read with zeros
  a::host::DeviceTimeouts timeouts{std::chrono::milliseconds(3000), std::chrono::milliseconds(3000)};
  a::host::ModbusDevice device("tcp://127.0.0.1:" + std::to_string(slave.port()), timeouts);
  json out;
  out["connect"] = slave.take_requests();
  out["calls"] = run_calls(
      device, in.at("calls"), [&](const json& read) { slave.set_registers(words_from(read.at("input_registers"))); },
      [&](json& result) { result["requests"] = slave.take_requests(); });
  return out;
}

// ---------------------------------------------------------------- host: CAN client
// A bus that records what is sent and hands out frames queued by the case (empty: timeout).
class ScriptedBus final : public a::io::CanBus {
 public:
  struct Shared {
    std::deque<a::io::CanFrame> incoming;
    std::vector<a::io::CanFrame> sent;
    std::vector<a::io::CanFilter> filters;
  };
  explicit ScriptedBus(std::shared_ptr<Shared> s) : s_(std::move(s)) {}
  a::io::CanResult send(const a::io::CanFrame& f) override {
    s_->sent.push_back(f);
    return {};
  }
  a::io::CanResult receive(a::io::CanFrame& f, std::chrono::milliseconds) override {
    if (s_->incoming.empty()) return {a::io::CanStatus::timeout, 0, "no frame"};
    f = s_->incoming.front();
    s_->incoming.pop_front();
    return {};
  }
  a::io::CanResult set_filters(std::span<const a::io::CanFilter> filters) override {
    s_->filters.assign(filters.begin(), filters.end());
    return {};
  }
  std::string name() const override { return "golden0"; }

 private:
  std::shared_ptr<Shared> s_;
};

json sent_frames(ScriptedBus::Shared& s) {
  json frames = json::array();
  for (const auto& f : s.sent) frames.push_back(frame_text(f));
  s.sent.clear();
  return frames;
}

json host_can_session(const json& in) {
  auto shared = std::make_shared<ScriptedBus::Shared>();
  for (const json& f : in.at("connect_frames")) shared->incoming.push_back(frame_from(f.get<std::string>()));
  a::host::DeviceTimeouts timeouts{std::chrono::milliseconds(200), std::chrono::milliseconds(200)};
  a::host::CanDevice device(std::make_unique<ScriptedBus>(shared), in.at("node").get<std::uint8_t>(), timeouts);
  json out;
  json filters = json::array();
  for (const auto& f : shared->filters)
    filters.push_back({{"id", hex_id(f.id)}, {"mask", hex_id(f.mask)}, {"extended", f.extended}});
  out["filters"] = filters;
  out["connect_sent"] = sent_frames(*shared);
  out["calls"] = run_calls(
      device, in.at("calls"),
      [&](const json& read) {
        for (const json& f : read.at("frames")) shared->incoming.push_back(frame_from(f.get<std::string>()));
      },
      [&](json& result) {
        result["sent"] = sent_frames(*shared);
        result["frames_left"] = shared->incoming.size();
      });
  return out;
}

using Runner = std::function<json(const json&)>;
const std::vector<std::pair<std::string, Runner>>& runners() {
  static const std::vector<std::pair<std::string, Runner>> list = {
      {"emu.codes", codes},
      {"emu.modbus.request", modbus_request},
      {"emu.modbus.holding_registers", modbus_holding},
      {"emu.modbus.input_registers", modbus_input},
      {"emu.modbus.exchange", modbus_exchange},
      {"emu.modbus.endpoint", modbus_endpoint},
      {"emu.can.ids", can_ids},
      {"emu.can.crc8", can_crc8},
      {"emu.can.command_encode", can_command_encode},
      {"emu.can.command_decode", can_command_decode},
      {"emu.can.aux_encode", can_aux_encode},
      {"emu.can.aux_decode", can_aux_decode},
      {"emu.can.alive_counter", can_alive},
      {"emu.can.telemetry_encode", can_telemetry_encode},
      {"emu.can.telemetry_decode", can_telemetry_decode},
      {"host.modbus.session", host_modbus_session},
      {"host.can.session", host_can_session},
  };
  return list;
}

}  // namespace

const std::vector<std::string>& codec_kinds() {
  static const std::vector<std::string> kinds = [] {
    std::vector<std::string> k;
    for (const auto& [name, run] : runners()) k.push_back(name);
    return k;
  }();
  return kinds;
}

json run_codec_case(const std::string& kind, const json& input) {
  for (const auto& [name, run] : runners()) {
    if (name == kind) return run(input);
  }
  throw std::invalid_argument("unknown codec case kind " + kind);
}

bool json_matches(const json& expected, const json& actual, double relative, std::string& where) {
  auto fail = [&](const std::string& what) {
    where = what;
    return false;
  };
  if (expected.is_number() && actual.is_number()) {
    if (expected.is_number_float() || actual.is_number_float()) {
      const double e = expected.get<double>(), x = actual.get<double>();
      if (e == x) return true;
      return std::abs(e - x) <= relative * std::max(std::abs(e), std::abs(x))
                 ? true
                 : fail(": " + expected.dump() + " vs " + actual.dump());
    }
    return expected == actual ? true : fail(": " + expected.dump() + " vs " + actual.dump());
  }
  if (expected.type() != actual.type()) return fail(": " + expected.dump() + " vs " + actual.dump());
  if (expected.is_object()) {
    for (const auto& [key, value] : expected.items()) {
      if (!actual.contains(key)) return fail("." + key + ": missing");
      if (!json_matches(value, actual.at(key), relative, where)) return fail("." + key + where);
    }
    for (const auto& [key, value] : actual.items()) {
      if (!expected.contains(key)) return fail("." + key + ": not expected");
    }
    return true;
  }
  if (expected.is_array()) {
    if (expected.size() != actual.size())
      return fail(": " + std::to_string(expected.size()) + " elements expected, " + std::to_string(actual.size()) +
                  " found");
    for (std::size_t i = 0; i < expected.size(); ++i) {
      if (!json_matches(expected[i], actual[i], relative, where)) return fail("[" + std::to_string(i) + "]" + where);
    }
    return true;
  }
  return expected == actual ? true : fail(": " + expected.dump() + " vs " + actual.dump());
}

}  // namespace swum::golden
