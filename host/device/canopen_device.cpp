#include "device/canopen_device.h"

#include <algorithm>
#include <charconv>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <thread>
#include <utility>

#include "device/can_receive.h"
#include "socketcan_bus.h"

namespace swum::host {

namespace layout = canopen_layout;

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kMinNode = 1;  // CiA 301 7.3.2: node ids 1..127
constexpr int kMaxNode = 127;
constexpr std::uint32_t kNmtId = 0x000;
constexpr std::uint32_t kSyncId = 0x080;
constexpr std::uint8_t kNmtStart = 0x01;                // CiA 301 7.2.8.3.1: start remote node
constexpr std::uint8_t kNmtEnterPreOperational = 0x80;  // enter pre-operational
constexpr std::uint32_t kHeartbeatBase = 0x700;         // boot-up (0x00) and heartbeat (NMT state)
constexpr std::uint32_t kSdoResponseBase = 0x580;
// A CiA 402 exchange walks one transition; enabling from switch on disabled takes three, each
// shown at the second SYNC after its controlword in lockstep: a lockstep walk gets this many.
constexpr int kWalkExchanges = 16;

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

std::string hex(std::uint32_t value, int digits) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%0*" PRIX32, digits, value);
  return text;
}

std::string object_name(std::uint16_t index, std::uint8_t sub) { return hex(index, 4) + " sub " + std::to_string(sub); }

std::string abort_text(canopen::SdoAbort code) {
  return hex(static_cast<std::uint32_t>(code), 8) + " " + canopen::describe(code);
}

protocol::CanFrame frame_of(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  protocol::CanFrame f;
  f.id = id;
  f.dlc = static_cast<std::uint8_t>(bytes.size());
  std::copy(bytes.begin(), bytes.end(), f.data.begin());
  return f;
}

std::unique_ptr<io::CanBus> open_bus(const std::string& interface) {
  try {
    return std::make_unique<io::SocketCanBus>(interface);
  } catch (const io::CanOpenError& e) {
    throw DeviceError(std::string("canopen ") + interface + ": " + e.what());
  }
}

struct Where {
  std::string interface;
  std::uint8_t node;
};
Where where(const std::string& address) {
  Where w{};
  w.node = parse_canopen_address(address, w.interface);
  return w;
}

const CanopenNode& checked(const CanopenNode& s) {
  if (s.sync_ticks > 65535) throw std::invalid_argument("--sync-ticks: must be within 1..65535");
  if (!(s.tick_hz > 0.0 && std::isfinite(s.tick_hz))) throw std::invalid_argument("--tick-hz: must be > 0");
  return s;
}

cia402::Goal goal_of(DeviceAction action, cia402::Goal current) {
  switch (action) {
    case DeviceAction::keep_alive: return current;
    case DeviceAction::enable: return cia402::Goal::on;
    case DeviceAction::disable: return cia402::Goal::off;
    case DeviceAction::reset_fault: return cia402::Goal::reset;
  }
  return current;
}

// A slew in the object's whole units, rounded down but never to 0 (0 is "unlimited").
std::uint32_t slew_units(double per_s, const char* what) {
  if (!(per_s >= 0.0 && per_s <= 4294967295.0)) throw DeviceError(std::string(what) + ": must be within 0..4294967295");
  return per_s > 0.0 ? std::max<std::uint32_t>(1, static_cast<std::uint32_t>(std::floor(per_s))) : 0;
}

}  // namespace

std::uint8_t parse_canopen_address(const std::string& address, std::string& interface) {
  const auto colon = address.rfind(':');
  if (colon == std::string::npos || colon == 0)
    throw std::invalid_argument("--canopen: expected IFACE:NODE (node 1..127), got '" + address + "'");
  interface = address.substr(0, colon);
  const std::string text = address.substr(colon + 1);
  int node = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), node);
  if (text.empty() || error != std::errc{} || end != text.data() + text.size() || node < kMinNode || node > kMaxNode)
    throw std::invalid_argument("--canopen: node must be an integer 1..127, got '" + text + "'");
  return static_cast<std::uint8_t>(node);
}

CanopenDevice::CanopenDevice(const std::string& address, const CanopenNode& settings, const DeviceTimeouts& timeouts)
    : CanopenDevice(
          [&] {
            const Where w = where(address);
            checked(settings);
            return open_bus(w.interface);
          }(),
          where(address).node, settings, timeouts) {}

CanopenDevice::CanopenDevice(std::unique_ptr<io::CanBus> bus, std::uint8_t node, const CanopenNode& settings,
                             const DeviceTimeouts& timeouts)
    : bus_(std::move(bus)),
      node_(node),
      settings_(checked(settings)),
      response_timeout_(timeouts.response),
      sdo_(node, std::chrono::duration_cast<std::chrono::nanoseconds>(timeouts.response).count()) {
  start(timeouts);
}

std::string CanopenDevice::name() const { return "canopen " + bus_->name() + " node " + std::to_string(node_); }

void CanopenDevice::send(const protocol::CanFrame& frame, const char* what) {
  // A full transmit queue is transient on a busy bus: retry briefly before giving up.
  for (int attempt = 0; attempt < 50; ++attempt) {
    const io::CanResult r = bus_->send(frame);
    if (r.ok()) return;
    if (r.status != io::CanStatus::retry) throw DeviceError(name() + ": sending the " + what + " failed: " + r.message);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  throw DeviceError(name() + ": transmit queue stayed full while sending the " + what + " (bus off?)");
}

void CanopenDevice::drain() {
  io::CanFrame f;
  for (;;) {
    const io::CanResult r = bus_->receive(f, std::chrono::milliseconds(0));
    if (r.ok()) {
      check_boot_up(f);
    } else if (r.status != io::CanStatus::error_frame) {
      return;  // empty (a failing bus is reported by the receive that waits)
    }
  }
}

// A boot-up message (0x700 + node, 0x00) once the node is configured: it was reset (by another
// master or its own power cycle) and has its default PDOs again.
void CanopenDevice::check_boot_up(const protocol::CanFrame& f) const {
  if (configured_ && !f.extended && f.id == kHeartbeatBase + node_ && f.dlc == 1 && f.data[0] == 0x00)
    throw DeviceError(name() + ": the node rebooted (boot-up message): its PDO configuration is gone");
}

void CanopenDevice::start(const DeviceTimeouts& timeouts) {
  const io::CanFilter filters[] = {
      {layout::tpdos()[0].cob_id(node_), io::kCanStandardIdMax, false},
      {layout::tpdos()[1].cob_id(node_), io::kCanStandardIdMax, false},
      {layout::tpdos()[2].cob_id(node_), io::kCanStandardIdMax, false},
      {layout::tpdos()[3].cob_id(node_), io::kCanStandardIdMax, false},
      {kSdoResponseBase + node_, io::kCanStandardIdMax, false},
      {kHeartbeatBase + node_, io::kCanStandardIdMax, false},
  };
  const io::CanResult r = bus_->set_filters(filters);
  if (!r.ok()) throw DeviceError(name() + ": cannot set receive filters: " + r.message);
  reach();
  configure();
  send(frame_of(kNmtId, {kNmtStart, node_}), "NMT start");
  configured_ = true;
  // The first SYNC proves the cycle (and, in lockstep, runs the node's first cycle).
  try {
    (void)sync_and_collect(timeouts.connect);
  } catch (const DeviceError& e) {
    throw DeviceError(std::string(e.what()) + " after NMT start (is the node in lockstep? give --sync-ticks only " +
                      "for swum-emu --clock external)");
  }
}

// The node is reached without a reset: NMT enter pre-operational (SDO works there, also for a
// node another master stopped) and an SDO read of the device type 0x1000, which only a present
// node answers. Not reset communication: CiA 402 counts a reset (and NMT stopped) as the
// master's connection aborted (0x6007), and a running drive would react to a second master's
// `swum log`; pre-operational is no such event. Whatever a previous master mapped is remapped by
// CiA 301's procedure in configure().
void CanopenDevice::reach() {
  drain();
  send(frame_of(kNmtId, {kNmtEnterPreOperational, node_}), "NMT enter pre-operational");
  try {
    device_type_ = upload(0x1000, 0, "device type");
  } catch (const DeviceError& e) {
    if (sdo_.abort_code() != canopen::SdoAbort::timeout) throw;
    throw DeviceError(name() + ": no answer to an SDO read of the device type within " +
                      std::to_string(response_timeout_.count()) + " ms (is swum-emu running with --can " +
                      bus_->name() + " --node " + std::to_string(node_) + " --can-profile cia402?)");
  }
}

void CanopenDevice::configure() {
  // CiA 402-2: device type 0x1000 bits 0-15 = 402 (0x0192); 0x6502 bit 16 = the first
  // manufacturer mode, -1.
  const std::uint32_t type = device_type_;  // read by reach()
  if ((type & 0xFFFF) != 0x0192)
    throw DeviceError(name() + ": not a CiA 402 drive (device type 0x1000 = " + hex(type, 8) + ", profile " +
                      std::to_string(type & 0xFFFF) + ")");
  const std::uint32_t modes = upload(0x6502, 0, "supported drive modes");
  if ((modes & (1U << 16)) == 0)
    throw DeviceError(name() + ": the drive does not offer the open-loop mode -1 (supported drive modes 0x6502 = " +
                      hex(modes, 8) + ", bit 16 clear)");
  download(0x6060, 0, static_cast<std::uint8_t>(canopen::kModeOpenLoop), 1, "modes of operation = -1");  // 0xFF
  for (const layout::Pdo& pdo : layout::tpdos())
    configure_pdo(pdo, static_cast<std::uint16_t>(0x1800 + pdo.number - 1),
                  static_cast<std::uint16_t>(0x1A00 + pdo.number - 1));
  for (const layout::Pdo& pdo : layout::rpdos())
    configure_pdo(pdo, static_cast<std::uint16_t>(0x1400 + pdo.number - 1),
                  static_cast<std::uint16_t>(0x1600 + pdo.number - 1));
  // RPDO3 and RPDO4 off: their default mappings (controlword, target velocity; 0x2001, 0x2002)
  // would take frames of other masters.
  download(0x1402, 1, (0x400U + node_) | layout::kCobIdNotValid, 4, "RPDO3 off");
  download(0x1403, 1, (0x500U + node_) | layout::kCobIdNotValid, 4, "RPDO4 off");
  // What the drive holds now: the RPDOs repeat it until the host sets its own.
  controlword_ = static_cast<std::uint16_t>(upload(0x6040, 0, "controlword"));
  encoded_.frequency_mhz = upload(0x2001, 0, "frequency set-point");
  encoded_.amplitude_mv = upload(0x2002, 0, "amplitude set-point");
  encoded_.phase_cdeg = static_cast<std::int16_t>(upload(0x2003, 0, "phase set-point"));
  setpoint_.frequency_hz = encoded_.frequency_mhz * 1e-3;
  setpoint_.amplitude_v = encoded_.amplitude_mv * 1e-3;
  setpoint_.phase_deg = encoded_.phase_cdeg * 0.01;
  setpoint_.load_n = 0.0;
}

// CiA 301 7.5.2.35-38: the PDO made invalid (COB-ID bit 31), its mapping emptied (sub 0 = 0),
// the entries written, the count, the transmission type, and the PDO made valid again.
void CanopenDevice::configure_pdo(const layout::Pdo& pdo, std::uint16_t communication, std::uint16_t mapping) {
  const std::uint32_t cob_id = pdo.cob_id(node_);
  download(communication, 1, cob_id | layout::kCobIdNotValid, 4, "PDO COB-ID (invalid)");
  download(mapping, 0, 0, 1, "PDO mapping count 0");
  for (std::size_t i = 0; i < pdo.entries.size(); ++i)
    download(mapping, static_cast<std::uint8_t>(i + 1), pdo.entries[i], 4, "PDO mapping entry");
  download(mapping, 0, static_cast<std::uint32_t>(pdo.entries.size()), 1, "PDO mapping count");
  download(communication, 2, pdo.transmission_type, 1, "PDO transmission type");
  download(communication, 1, cob_id, 4, "PDO COB-ID (valid)");
}

void CanopenDevice::transfer(protocol::CanFrame request, std::uint16_t index, std::uint8_t sub, const char* what) {
  const std::string object = object_name(index, sub);
  send(request, "SDO request");
  for (;;) {
    protocol::CanFrame next;
    canopen::SdoProgress progress = sdo_.poll(now_ns(), next);
    if (progress == canopen::SdoProgress::ignored) {
      // Short waits: the client's own timeout (poll) ends a transfer the node left unanswered.
      io::CanFrame f;
      if (!receive_until(*bus_, Clock::now() + std::chrono::milliseconds(10), f, name())) continue;
      progress = sdo_.receive(f, now_ns(), next);
    }
    switch (progress) {
      case canopen::SdoProgress::ignored: break;
      case canopen::SdoProgress::send: send(next, "SDO request"); break;
      case canopen::SdoProgress::done: return;
      case canopen::SdoProgress::aborted:
        throw DeviceError(name() + ": " + what + " (" + object + ") refused by the node: SDO abort " +
                          abort_text(sdo_.abort_code()));
      case canopen::SdoProgress::failed:
        send(next, "SDO abort");
        throw DeviceError(name() + ": " + what + " (" + object +
                          "): the host aborted the SDO transfer: " + abort_text(sdo_.abort_code()) +
                          (sdo_.abort_code() == canopen::SdoAbort::timeout
                               ? " (no answer within " + std::to_string(response_timeout_.count()) + " ms)"
                               : std::string()));
    }
  }
}

std::uint32_t CanopenDevice::upload(std::uint16_t index, std::uint8_t sub, const char* what) {
  std::array<std::uint8_t, 4> bytes{};
  protocol::CanFrame request;
  sdo_.start_upload(index, sub, bytes, now_ns(), request);
  transfer(request, index, sub, what);
  std::uint32_t value = 0;
  const auto data = sdo_.uploaded();
  for (std::size_t i = 0; i < data.size(); ++i) value |= std::uint32_t{data[i]} << (8 * i);
  return value;
}

void CanopenDevice::download(std::uint16_t index, std::uint8_t sub, std::uint32_t value, std::size_t bytes,
                             const char* what) {
  const std::array<std::uint8_t, 4> data{static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8),
                                         static_cast<std::uint8_t>(value >> 16),
                                         static_cast<std::uint8_t>(value >> 24)};
  protocol::CanFrame request;
  sdo_.start_download(index, sub, std::span<const std::uint8_t>(data.data(), bytes), now_ns(), request);
  transfer(request, index, sub, what);
}

void CanopenDevice::check_setpoint(const DriveSetpoint& s) {
  if (s.load_n != 0.0)
    throw DeviceError(name() + ": the CiA 402 drive has no load input (load " + std::to_string(s.load_n) +
                      " N asked): set the emulated load with swum-emu's scenario, --inject or HTTP API");
  layout::Setpoints encoded;
  const std::string problem = layout::encode_setpoints(s, encoded);
  if (!problem.empty()) throw DeviceError(name() + ": " + problem);
  setpoint_ = s;
  encoded_ = encoded;
}

void CanopenDevice::write_slews(const DriveSlew& slew) {
  const std::uint32_t hz = slew_units(slew.frequency_hz_per_s, "frequency slew (Hz/s)");
  const std::uint32_t v = slew_units(slew.amplitude_v_per_s, "amplitude slew (V/s)");
  download(0x2004, 0, hz, 4, "frequency slew");
  download(0x2005, 0, v, 4, "amplitude slew");
  slew_ = slew;
  slews_known_ = true;
}

void CanopenDevice::send_setpoints() { send(layout::rpdo1(node_, encoded_), "RPDO1 (frequency, amplitude)"); }

void CanopenDevice::send_controlword(std::uint16_t controlword) {
  controlword_ = controlword;
  send(layout::rpdo2(node_, controlword, encoded_), "RPDO2 (controlword, phase)");
}

void CanopenDevice::walk_one() {
  if (cia402::reached(state_, goal_)) return;
  send_controlword(cia402::next_controlword(state_, goal_, controlword_));
}

void CanopenDevice::set_drive(const DriveSetpoint& s) {
  check_setpoint(s);
  send_setpoints();
  send_controlword(controlword_);
}

void CanopenDevice::set_slew(double frequency_hz_per_s, double amplitude_v_per_s) {
  write_slews(DriveSlew{frequency_hz_per_s, amplitude_v_per_s});
}

void CanopenDevice::command(DeviceAction action) {
  goal_ = goal_of(action, goal_);
  // In lockstep a walk costs cycles (each exchange is one): a bounded number. On the wall clock
  // the drive takes its transitions at its own tick rate: a bounded time, and the bus is not
  // flooded while the state stays as it was.
  const auto deadline = Clock::now() + response_timeout_;
  for (int exchange = 0; !lockstep() || exchange < kWalkExchanges; ++exchange) {
    if (cia402::reached(state_, goal_)) return;
    // A fault ends only with a reset: the caller sees the state and decides.
    if (goal_ != cia402::Goal::reset && cia402::amp_state(state_) == protocol::AmpState::fault) return;
    const canopen::Cia402State before = state_;
    walk_one();
    (void)sync_and_collect(response_timeout_);
    if (lockstep()) continue;
    if (Clock::now() > deadline) return;  // later reads carry the walk on
    if (state_ == before) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

DeviceTelemetry CanopenDevice::read() {
  if (goal_ == cia402::Goal::reset || cia402::amp_state(state_) != protocol::AmpState::fault) walk_one();
  return sync_and_collect(response_timeout_);
}

DeviceTelemetry CanopenDevice::step(const DriveSetpoint& s, const DriveSlew& slew, DeviceAction action,
                                    std::uint32_t ticks) {
  if (!lockstep())
    throw DeviceError(name() + ": not in lockstep (give --sync-ticks N for a node run with swum-emu --clock external " +
                      "--sync-ticks N)");
  if (ticks == 0 || ticks % settings_.sync_ticks != 0)
    throw DeviceError(name() + ": a step of " + std::to_string(ticks) + " ticks is not a whole number of the node's " +
                      std::to_string(settings_.sync_ticks) + "-tick SYNC cycles (--sync-ticks; the control cycle " +
                      "--cycle-ms x --tick-hz / 1000 must be a multiple of it)");
  check_setpoint(s);
  if (!slews_known_ || slew.frequency_hz_per_s != slew_.frequency_hz_per_s ||
      slew.amplitude_v_per_s != slew_.amplitude_v_per_s)
    write_slews(slew);
  goal_ = goal_of(action, goal_);
  send_setpoints();
  send_controlword(cia402::next_controlword(state_, goal_, controlword_));
  DeviceTelemetry t;
  for (std::uint32_t sync = 0; sync < ticks / settings_.sync_ticks; ++sync) t = sync_and_collect(response_timeout_);
  return t;
}

DeviceTelemetry CanopenDevice::sync_and_collect(std::chrono::milliseconds timeout) {
  drain();  // TPDOs of an earlier SYNC that came too late: never taken for this one's
  send(frame_of(kSyncId, {}), "SYNC");
  ++syncs_;
  layout::Actuals actuals;
  unsigned seen = 0;
  constexpr unsigned kAll = 0x0F;
  const auto deadline = Clock::now() + timeout;
  io::CanFrame f;
  while (seen != kAll && receive_until(*bus_, deadline, f, name())) {
    check_boot_up(f);
    for (const layout::Pdo& pdo : layout::tpdos()) {
      if (f.extended || f.id != pdo.cob_id(node_)) continue;
      const std::string problem = layout::decode_tpdo(pdo.number, f, actuals);
      if (!problem.empty()) throw DeviceError(name() + ": " + problem);
      seen |= 1U << (pdo.number - 1);
    }
  }
  if (seen != kAll) {
    std::string missing;
    for (int n = 1; n <= 4; ++n)
      if ((seen & (1U << (n - 1))) == 0) missing += (missing.empty() ? "TPDO" : ", TPDO") + std::to_string(n);
    throw DeviceError(name() + ": " + missing + " did not answer the SYNC within " + std::to_string(timeout.count()) +
                      " ms");
  }
  DeviceTelemetry t = layout::telemetry_of(actuals);
  state_ = canopen::state_of(actuals.statusword);
  if (lockstep()) {
    // Sampled at the SYNC, before the cycle it starts: the host's SYNCs before it are the time.
    t.lockstep = true;
    t.tick = (syncs_ - 1) * settings_.sync_ticks;
    t.device_time_s = static_cast<double>(*t.tick) / settings_.tick_hz;
  }
  return t;
}

}  // namespace swum::host
