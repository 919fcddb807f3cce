// The CAN adapter of host/device/device.h. Commands: the Command frame (mode + frequency + phase +
// amplitude, alive counter, CRC) and the AuxCommand frame (load, slew limits); a keep-alive
// repeats the Command frame with the current mode. Telemetry: one sample per Status frame,
// completed by the Motion, Drive, LoopStats, Clock and Output frames the emulator sends after it;
// the ElectricalA/B frames (before Output) are optional: without them the sample has no
// electrical values and no stator temperature (a board of the older protocol leaves Status
// bytes 6-7 free, so they are read only from a node that sends the electrical frames).
#include "device/can_device.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include "can_codec.h"
#include "can_telemetry_decode.h"
#include "device/can_receive.h"
#include "socketcan_bus.h"

namespace swum::host {

namespace can = protocol::can;
namespace {

std::uint8_t parse_node(const std::string& address, std::string& interface) {
  const auto colon = address.find(':');
  interface = address.substr(0, colon);
  if (interface.empty()) throw std::invalid_argument("--can: expected IFACE[:NODE], got '" + address + "'");
  if (colon == std::string::npos) return 1;
  const std::string text = address.substr(colon + 1);
  int node = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), node);
  if (error != std::errc{} || end != text.data() + text.size() || node < can::kMinNode || node > can::kMaxNode) {
    throw std::invalid_argument("--can: node must be an integer " + std::to_string(can::kMinNode) + ".." +
                                std::to_string(can::kMaxNode) + ", got '" + text + "'");
  }
  return static_cast<std::uint8_t>(node);
}

std::unique_ptr<io::CanBus> open_bus(const std::string& interface) {
  try {
    return std::make_unique<io::SocketCanBus>(interface);
  } catch (const io::CanOpenError& e) {
    throw DeviceError(std::string("can ") + interface + ": " + e.what());
  }
}

}  // namespace

CanDevice::CanDevice(const std::string& address, const DeviceTimeouts& timeouts) {
  std::string interface;
  node_ = parse_node(address, interface);
  bus_ = open_bus(interface);
  start(timeouts);
}

CanDevice::CanDevice(std::unique_ptr<io::CanBus> bus, std::uint8_t node, const DeviceTimeouts& timeouts)
    : bus_(std::move(bus)), node_(node) {
  start(timeouts);
}

void CanDevice::start(const DeviceTimeouts& timeouts) {
  const can::Ids ids = can::ids_for_node(node_);
  auto exact = [](std::uint32_t id) { return io::CanFilter{id, io::kCanStandardIdMax, false}; };
  const io::CanFilter filters[] = {exact(ids.status),       exact(ids.motion),      exact(ids.drive),
                                   exact(ids.loop_stats),   exact(ids.output),      exact(ids.clock),
                                   exact(ids.electrical_a), exact(ids.electrical_b)};
  const io::CanResult r = bus_->set_filters(filters);
  if (!r.ok()) throw DeviceError(name() + ": cannot set receive filters: " + r.message);
  // The node must be talking before anyone relies on it. A lockstep node (--clock external)
  // only talks when stepped: after a short silence one SYNC asks it (that cycle is run).
  response_timeout_ = std::min(timeouts.connect, std::chrono::milliseconds(200));
  try {
    try {
      lockstep_ = read().lockstep;
    } catch (const DeviceError&) {
      send_sync();
      response_timeout_ = timeouts.connect;
      const DeviceTelemetry t = receive_set();
      lockstep_ = t.lockstep;
      if (lockstep_) last_sync_answer_ = t;
      last_tick_ = t.tick ? std::optional<std::uint32_t>(static_cast<std::uint32_t>(*t.tick)) : std::nullopt;
    }
  } catch (const DeviceError&) {
    throw DeviceError(name() + ": no answer from node " + std::to_string(node_) + " within " +
                      std::to_string(timeouts.connect.count()) + " ms (is swum-emu running with --can " + bus_->name() +
                      " --node " + std::to_string(node_) + " and CAN telemetry on?)");
  }
  response_timeout_ = timeouts.response;
}

std::string CanDevice::name() const { return "can " + bus_->name() + " node " + std::to_string(node_); }

void CanDevice::send(const io::CanFrame& frame, const char* what) {
  // A full transmit queue is transient on a busy bus: retry briefly before giving up.
  for (int attempt = 0; attempt < 50; ++attempt) {
    const io::CanResult r = bus_->send(frame);
    if (r.ok()) return;
    if (r.status != io::CanStatus::retry)
      throw DeviceError(name() + ": sending the " + what + " frame failed: " + r.message);
    io::CanFrame ignored;
    (void)bus_->receive(ignored, std::chrono::milliseconds(1));
  }
  throw DeviceError(name() + ": transmit queue stayed full while sending the " + what + " frame (bus off?)");
}

void CanDevice::send_command(std::uint8_t mode) {
  can::CommandFrame c;
  c.mode = mode;
  command_alive_ = can::next_alive(command_alive_);
  c.alive = command_alive_;
  c.frequency_hz = setpoint_.frequency_hz;
  c.phase_deg = setpoint_.phase_deg;
  c.amplitude_v = setpoint_.amplitude_v;
  send(can::encode_command(c, can::ids_for_node(node_).command), "command");
}

void CanDevice::send_aux() {
  can::AuxFrame a;
  aux_alive_ = can::next_alive(aux_alive_);
  a.alive = aux_alive_;
  a.load_n = setpoint_.load_n;
  a.frequency_slew_hz_per_s = frequency_slew_hz_per_s_;
  a.amplitude_slew_v_per_s = amplitude_slew_v_per_s_;
  send(can::encode_aux(a, can::ids_for_node(node_).aux), "aux command");
}

void CanDevice::set_drive(const DriveSetpoint& s) {
  const bool load_changed = s.load_n != setpoint_.load_n;
  setpoint_ = s;
  if (load_changed) send_aux();
  send_command(mode_);
}

void CanDevice::set_slew(double frequency_hz_per_s, double amplitude_v_per_s) {
  // The AuxCommand frame carries 100 Hz/s and 10 V/s steps, 0 = unlimited: round down to a
  // step, never to 0, so the device never slews faster than asked.
  auto down = [](double v, double step) { return v > 0.0 ? std::max(step, std::floor(v / step) * step) : 0.0; };
  frequency_slew_hz_per_s_ = down(frequency_hz_per_s, can::signals::kAuxFrequencySlew.factor);
  amplitude_slew_v_per_s_ = down(amplitude_v_per_s, can::signals::kAuxAmplitudeSlew.factor);
  send_aux();
}

void CanDevice::command(DeviceAction action) {
  switch (action) {
    case DeviceAction::keep_alive: send_command(mode_); break;
    case DeviceAction::enable:
      mode_ = can::mode::kEnable;
      send_command(mode_);
      break;
    case DeviceAction::disable:
      mode_ = can::mode::kDisable;
      send_command(mode_);
      break;
    case DeviceAction::reset_fault:
      mode_ = can::mode::kDisable;
      send_command(can::mode::kResetFault);
      break;
  }
}

void CanDevice::send_sync() {
  sync_counter_ = static_cast<std::uint8_t>(sync_counter_ % can::kMaxSyncCounter + 1);
  send(can::encode_sync(sync_counter_), "SYNC");
}

DeviceTelemetry CanDevice::step(const DriveSetpoint& s, const DriveSlew& slew, DeviceAction action,
                                std::uint32_t ticks) {
  if (!lockstep_) throw DeviceError(name() + ": not in lockstep (start swum-emu with --clock external)");
  const bool aux_changed = s.load_n != setpoint_.load_n || slew.frequency_hz_per_s != frequency_slew_hz_per_s_ ||
                           slew.amplitude_v_per_s != amplitude_slew_v_per_s_;
  setpoint_ = s;
  if (aux_changed) {
    frequency_slew_hz_per_s_ = slew.frequency_hz_per_s;
    amplitude_slew_v_per_s_ = slew.amplitude_v_per_s;
    send_aux();
  }
  command(action);  // the Command frame with the set-points, latched at the SYNC below
  send_sync();
  DeviceTelemetry t = receive_set();
  last_sync_answer_ = t;
  if (t.tick) {
    const auto tick = static_cast<std::uint32_t>(*t.tick);
    if (last_tick_ && tick - *last_tick_ != ticks)
      throw DeviceError(name() + ": the device ran " + std::to_string(tick - *last_tick_) +
                        " ticks per SYNC, the controller steps " + std::to_string(ticks) +
                        " (swum-emu --sync-ticks must equal --cycle-ms x --tick-hz / 1000)");
    last_tick_ = tick;
  }
  return t;
}

DeviceTelemetry CanDevice::read() {
  // In lockstep the node talks only when a SYNC steps it: the telemetry of the last SYNC.
  if (lockstep_ && last_sync_answer_) return *last_sync_answer_;
  return receive_set();
}

DeviceTelemetry CanDevice::receive_set() {
  const can::Ids ids = can::ids_for_node(node_);
  DeviceTelemetry t;
  bool have_status = false;
  // Frames of the current set seen after its Status frame: a set with a frame lost is
  // discarded (the status counter then shows the gap), never returned with zeros in it.
  enum : unsigned { kMotion = 1, kDrive = 2, kLoopStats = 4, kClock = 8, kAll = 15 };
  unsigned seen = 0;
  // Optional frames of the set: both electrical frames, or the sample has no electrical values.
  enum : unsigned { kElectricalA = 1, kElectricalB = 2, kBothPhases = 3 };
  unsigned electrical_seen = 0;
  protocol::ElectricalValues electrical;
  double stator_temperature_c = 0.0;
  const auto deadline = std::chrono::steady_clock::now() + response_timeout_;
  io::CanFrame f;
  while (receive_until(*bus_, deadline, f, name())) {
    if (f.id == ids.status) {
      can::StatusFields s;
      if (can::decode_status(f, s) != protocol::Reason::none) continue;
      t = DeviceTelemetry{};
      have_status = true;
      seen = 0;
      electrical_seen = 0;
      stator_temperature_c = s.stator_temperature_c;
      t.sample_counter = s.status_counter;
      t.sample_counter_modulus = 1U << can::signals::kStatusCounter.length;
      t.state = s.state;
      t.fault_code = s.fault;
      t.drive_on = s.drive_on;
      t.enable_line = s.enable_line;
      t.lockstep = s.external_clock;
      t.last_reject = s.last_reject;
      t.reject_count = s.reject_count;
      t.reject_count_modulus = 1U << can::signals::kStatusRejectCount.length;
    } else if (!have_status) {
      continue;  // the middle of a set whose status frame we missed
    } else if (f.id == ids.motion) {
      can::MotionFields m;
      if (can::decode_motion(f, m) == protocol::Reason::none) {
        t.speed_mm_s = m.speed_mm_s;
        t.position_mm = m.position_mm;
        seen |= kMotion;
      }
    } else if (f.id == ids.drive) {
      can::DriveFields d;
      if (can::decode_drive(f, d) == protocol::Reason::none) {
        t.tip_normal_um = d.tip_normal_um;
        t.tip_tangential_um = d.tip_tangential_um;
        t.amplitude_v = d.amplitude_v;
        t.phase_deg = d.phase_deg;
        seen |= kDrive;
      }
    } else if (f.id == ids.loop_stats) {
      can::LoopStatsFields l;
      if (can::decode_loop_stats(f, l) == protocol::Reason::none) {
        t.lateness_p99_us = l.lateness_p99_us;
        t.lateness_max_us = l.lateness_max_us;
        t.overruns = l.overruns;
        seen |= kLoopStats;
      }
    } else if (f.id == ids.clock) {
      can::ClockFields c;
      if (can::decode_clock(f, c) == protocol::Reason::none) {
        t.device_time_s = c.sim_time_s;
        t.tick = c.tick;
        seen |= kClock;
      }
    } else if (f.id == ids.electrical_a || f.id == ids.electrical_b) {
      can::ElectricalFields e;
      if (can::decode_electrical(f, e) == protocol::Reason::none) {
        const bool a = f.id == ids.electrical_a;
        (a ? electrical.current_a_a : electrical.current_b_a) = e.current_a;
        (a ? electrical.phase_a_deg : electrical.phase_b_deg) = e.phase_deg;
        (a ? electrical.motional_phase_a_deg : electrical.motional_phase_b_deg) = e.motional_phase_deg;
        (a ? electrical.power_a_w : electrical.power_b_w) = e.power_w;
        electrical_seen |= a ? kElectricalA : kElectricalB;
      }
    } else if (f.id == ids.output) {
      can::OutputFields o;
      if (seen != kAll) {
        have_status = false;  // incomplete set: wait for the next Status frame
        continue;
      }
      if (can::decode_output(f, o) == protocol::Reason::none) {
        t.frequency_hz = o.frequency_hz;
        t.load_n = o.load_n;
        if (electrical_seen == kBothPhases) {
          t.electrical = electrical;
          t.stator_temperature_c = stator_temperature_c;
        }
        t.received = std::chrono::steady_clock::now();
        return t;  // the set is complete
      }
    }
  }
  throw DeviceError(name() + ": no telemetry within " + std::to_string(response_timeout_.count()) + " ms");
}

}  // namespace swum::host
