#include "can_codec.h"

#include <algorithm>
#include <cmath>

namespace swum::protocol::can {

namespace {
std::uint64_t raw_unsigned(double physical, double factor, unsigned bits) {
  const double max = std::ldexp(1.0, static_cast<int>(bits)) - 1.0;
  if (!(physical > 0.0)) return 0;
  return static_cast<std::uint64_t>(std::min(std::round(physical / factor), max));
}
std::uint64_t raw_signed(double physical, double factor, unsigned bits) {
  const double half = std::ldexp(1.0, static_cast<int>(bits) - 1);
  double r = std::isfinite(physical) ? std::round(physical / factor) : 0.0;
  r = std::clamp(r, -half, half - 1.0);
  const auto v = static_cast<std::int64_t>(r);
  return static_cast<std::uint64_t>(v) & ((bits == 64) ? ~0ULL : ((1ULL << bits) - 1));
}
std::int64_t sign_extend(std::uint64_t raw, unsigned bits) {
  const std::uint64_t sign = 1ULL << (bits - 1);
  return static_cast<std::int64_t>((raw ^ sign) - sign);
}
std::uint16_t us(std::uint64_t ns) { return static_cast<std::uint16_t>(std::min<std::uint64_t>(ns / 1000, 65535)); }
}  // namespace

Ids ids_for_node(std::uint8_t node) {
  return {0x200U + node, 0x300U + node, 0x180U + node, 0x280U + node, 0x380U + node, 0x480U + node,
          0x500U + node, 0x700U + node, 0x580U + node, 0x680U + node, 0x780U + node};
}

std::uint8_t crc8(std::uint32_t id, const std::uint8_t* data, std::size_t length) {
  std::uint8_t crc = 0xFF;
  auto feed = [&](std::uint8_t byte) {
    crc ^= byte;
    for (int i = 0; i < 8; ++i) crc = static_cast<std::uint8_t>((crc & 0x80U) ? (crc << 1) ^ 0x1DU : (crc << 1));
  };
  feed(static_cast<std::uint8_t>(id & 0xFFU));
  feed(static_cast<std::uint8_t>((id >> 8) & 0xFFU));
  for (std::size_t i = 0; i < length; ++i) feed(data[i]);
  return static_cast<std::uint8_t>(crc ^ 0xFFU);
}

std::uint64_t get_bits(const CanFrame& f, unsigned start, unsigned length) {
  std::uint64_t payload = 0;
  for (unsigned i = 0; i < 8; ++i) payload |= static_cast<std::uint64_t>(f.data[i]) << (8 * i);
  const std::uint64_t mask = length >= 64 ? ~0ULL : ((1ULL << length) - 1);
  return (payload >> start) & mask;
}

void put_bits(CanFrame& f, unsigned start, unsigned length, std::uint64_t raw) {
  std::uint64_t payload = 0;
  for (unsigned i = 0; i < 8; ++i) payload |= static_cast<std::uint64_t>(f.data[i]) << (8 * i);
  const std::uint64_t mask = length >= 64 ? ~0ULL : ((1ULL << length) - 1);
  payload = (payload & ~(mask << start)) | ((raw & mask) << start);
  for (unsigned i = 0; i < 8; ++i) f.data[i] = static_cast<std::uint8_t>(payload >> (8 * i));
}

std::uint64_t raw_value(const CanFrame& f, Signal s) { return get_bits(f, s.start, s.length); }
double physical_value(const CanFrame& f, Signal s) {
  const std::uint64_t raw = raw_value(f, s);
  return (s.is_signed ? static_cast<double>(sign_extend(raw, s.length)) : static_cast<double>(raw)) * s.factor;
}
void put_raw(CanFrame& f, Signal s, std::uint64_t raw) { put_bits(f, s.start, s.length, raw); }
void put_physical(CanFrame& f, Signal s, double physical) {
  put_raw(f, s, s.is_signed ? raw_signed(physical, s.factor, s.length) : raw_unsigned(physical, s.factor, s.length));
}

namespace {
CanFrame blank(std::uint32_t id, std::uint8_t dlc) {
  CanFrame f;
  f.id = id;
  f.extended = false;
  f.dlc = dlc;
  return f;
}
void seal(CanFrame& f) { f.data[7] = crc8(f.id, f.data.data()); }
}  // namespace

CanFrame encode_command(const CommandFrame& c, std::uint32_t id) {
  CanFrame f = blank(id, 8);
  put_raw(f, signals::kCommandMode, c.mode);
  put_raw(f, signals::kCommandAlive, c.alive);
  put_physical(f, signals::kCommandFrequency, c.frequency_hz);
  put_physical(f, signals::kCommandPhase, c.phase_deg);
  put_physical(f, signals::kCommandAmplitude, c.amplitude_v);
  seal(f);
  return f;
}

CanFrame encode_aux(const AuxFrame& a, std::uint32_t id) {
  CanFrame f = blank(id, 8);
  put_raw(f, signals::kAuxAlive, a.alive);
  put_physical(f, signals::kAuxLoad, a.load_n);
  put_physical(f, signals::kAuxFrequencySlew, a.frequency_slew_hz_per_s);
  put_physical(f, signals::kAuxAmplitudeSlew, a.amplitude_slew_v_per_s);
  seal(f);
  return f;
}

namespace {
Reason check_frame(const CanFrame& f) {
  if (f.extended || f.dlc != 8) return Reason::wrong_length;
  if (crc8(f.id, f.data.data()) != f.data[7]) return Reason::bad_checksum;
  return Reason::none;
}
}  // namespace

Reason decode_command(const CanFrame& f, CommandFrame& out) {
  if (const Reason r = check_frame(f); r != Reason::none) return r;
  if (raw_value(f, signals::kCommandReservedLow) != 0 || raw_value(f, signals::kCommandReservedHigh) != 0)
    return Reason::reserved_bits;
  out.mode = static_cast<std::uint8_t>(raw_value(f, signals::kCommandMode));
  out.alive = static_cast<std::uint8_t>(raw_value(f, signals::kCommandAlive));
  out.frequency_hz = physical_value(f, signals::kCommandFrequency);
  out.phase_deg = physical_value(f, signals::kCommandPhase);
  out.amplitude_v = physical_value(f, signals::kCommandAmplitude);
  if (out.mode > mode::kResetFault) return Reason::unknown_command;
  return Reason::none;
}

Reason decode_aux(const CanFrame& f, AuxFrame& out) {
  if (const Reason r = check_frame(f); r != Reason::none) return r;
  if (raw_value(f, signals::kAuxReserved) != 0) return Reason::reserved_bits;
  out.alive = static_cast<std::uint8_t>(raw_value(f, signals::kAuxAlive));
  out.load_n = physical_value(f, signals::kAuxLoad);
  out.frequency_slew_hz_per_s = physical_value(f, signals::kAuxFrequencySlew);
  out.amplitude_slew_v_per_s = physical_value(f, signals::kAuxAmplitudeSlew);
  return Reason::none;
}

Command to_command(const CommandFrame& c) {
  Command cmd;
  cmd.source = CommandSource::can;
  cmd.fields = Command::kAction | Command::kFrequency | Command::kAmplitude | Command::kPhase;
  cmd.action = c.mode == mode::kDisable  ? Action::disable
               : c.mode == mode::kEnable ? Action::enable
                                         : Action::reset_fault;
  cmd.frequency_hz = c.frequency_hz;
  cmd.amplitude_v = c.amplitude_v;
  cmd.phase_deg = c.phase_deg;
  return cmd;
}

Command to_command(const AuxFrame& a) {
  Command cmd;
  cmd.source = CommandSource::can;
  cmd.fields = Command::kLoad | Command::kFrequencySlew | Command::kAmplitudeSlew;
  cmd.load_n = a.load_n;
  cmd.frequency_slew_hz_per_s = a.frequency_slew_hz_per_s;
  cmd.amplitude_slew_v_per_s = a.amplitude_slew_v_per_s;
  return cmd;
}

Reason AliveCounter::check(std::uint8_t alive, std::int64_t now_ns) const {
  if (!seen_ || now_ns - last_ns_ > kAliveResyncNs) return Reason::none;
  const unsigned delta = (static_cast<unsigned>(alive) - last_) & 0x0FU;
  return (delta >= 1 && delta <= 7) ? Reason::none : Reason::stale_alive_counter;
}

CanFrame encode_status(const Telemetry& t, const RejectSnapshot& r, std::uint8_t counter, std::uint32_t id) {
  CanFrame f = blank(id, 8);
  put_raw(f, signals::kStatusState, static_cast<std::uint8_t>(t.state));
  put_raw(f, signals::kStatusEnableLine, t.enable_line ? 1 : 0);
  put_raw(f, signals::kStatusDriveOn, drive_on(t) ? 1 : 0);
  put_raw(f, signals::kStatusAtSetpoint, t.at_setpoint ? 1 : 0);
  put_raw(f, signals::kStatusExternalClock, t.external_clock ? 1 : 0);
  put_raw(f, signals::kStatusFault, static_cast<std::uint8_t>(t.fault));
  put_raw(f, signals::kStatusLastReject, static_cast<std::uint8_t>(r.last));
  put_raw(f, signals::kStatusRejectCount, r.count & 0xFFU);
  put_raw(f, signals::kStatusAppliedCount, t.applied_commands & 0xFFU);
  put_raw(f, signals::kStatusCounter, counter);
  put_physical(f, signals::kStatusStatorTemperature, t.stator_temperature_c);
  return f;
}

CanFrame encode_motion(const Telemetry& t, std::uint32_t id) {
  CanFrame f = blank(id, 8);
  put_physical(f, signals::kMotionSpeed, t.speed_m_s * 1e6);      // m/s -> um/s
  put_physical(f, signals::kMotionPosition, t.position_m * 1e6);  // m -> um
  return f;
}

CanFrame encode_drive(const Telemetry& t, std::uint32_t id) {
  CanFrame f = blank(id, 8);
  put_physical(f, signals::kDriveTipNormal, t.tip_normal_um);
  put_physical(f, signals::kDriveTipTangential, t.tip_tangential_um);
  put_physical(f, signals::kDriveAmplitude, t.output.amplitude_v);
  put_physical(f, signals::kDrivePhase, t.output.phase_deg);
  return f;
}

CanFrame encode_loop_stats(const Telemetry& t, std::uint32_t id) {
  CanFrame f = blank(id, 8);
  put_raw(f, signals::kLoopLatenessP99, us(t.stats.lateness_p99_ns));
  put_raw(f, signals::kLoopLatenessP999, us(t.stats.lateness_p999_ns));
  put_raw(f, signals::kLoopLatenessMax, us(t.stats.lateness_max_ns));
  put_raw(f, signals::kLoopOverruns, std::min<std::uint64_t>(t.stats.overruns, 65535));
  return f;
}

CanFrame encode_output(const Telemetry& t, std::uint32_t id) {
  CanFrame f = blank(id, 8);
  put_physical(f, signals::kOutputFrequency, t.output.frequency_hz);
  put_physical(f, signals::kOutputLoad, t.output.load_n);
  put_raw(f, signals::kOutputLatenessP50, us(t.stats.lateness_p50_ns));
  return f;
}

CanFrame encode_clock(const Telemetry& t, std::uint32_t id) {
  CanFrame f = blank(id, 8);
  const double ms = std::isfinite(t.sim_time_s) && t.sim_time_s > 0.0 ? std::floor(t.sim_time_s * 1e3) : 0.0;
  put_raw(f, signals::kClockTime, static_cast<std::uint64_t>(std::fmod(ms, 4294967296.0)));
  put_raw(f, signals::kClockTick, t.tick & 0xFFFFFFFFULL);
  return f;
}

namespace {
CanFrame encode_electrical(double current_a, double phase_deg, double motional_phase_deg, double power_w,
                           std::uint32_t id) {
  CanFrame f = blank(id, 8);
  put_physical(f, signals::kElectricalCurrent, current_a);
  put_physical(f, signals::kElectricalPhase, phase_deg);
  put_physical(f, signals::kElectricalMotionalPhase, motional_phase_deg);
  put_physical(f, signals::kElectricalPower, power_w);
  return f;
}
}  // namespace

CanFrame encode_electrical_a(const Telemetry& t, std::uint32_t id) {
  const ElectricalValues& e = t.electrical;
  return encode_electrical(e.current_a_a, e.phase_a_deg, e.motional_phase_a_deg, e.power_a_w, id);
}

CanFrame encode_electrical_b(const Telemetry& t, std::uint32_t id) {
  const ElectricalValues& e = t.electrical;
  return encode_electrical(e.current_b_a, e.phase_b_deg, e.motional_phase_b_deg, e.power_b_w, id);
}

CanFrame encode_heartbeat(std::uint32_t id) {
  CanFrame f = blank(id, 1);
  f.data[0] = signals::kHeartbeatOperational;
  return f;
}

Reason decode_sync(const CanFrame& f, SyncFrame& out) {
  if (f.dlc > 1) return Reason::wrong_length;
  out = {};
  if (f.dlc == 1) {
    if (f.data[0] < 1 || f.data[0] > kMaxSyncCounter) return Reason::unknown_command;
    out.has_counter = true;
    out.counter = f.data[0];
  }
  return Reason::none;
}

CanFrame encode_sync(std::uint8_t counter) {
  CanFrame f = blank(kSyncId, counter == 0 ? 0 : 1);
  if (counter != 0) f.data[0] = counter;
  return f;
}

}  // namespace swum::protocol::can
