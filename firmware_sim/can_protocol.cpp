#include "can_protocol.h"

#include <algorithm>
#include <cmath>

namespace swum::emu::can {

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
  return {0x200U + node, 0x300U + node, 0x180U + node, 0x280U + node,
          0x380U + node, 0x480U + node, 0x500U + node, 0x700U + node, 0x580U + node};
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

std::uint64_t get_bits(const io::CanFrame& f, unsigned start, unsigned length) {
  std::uint64_t payload = 0;
  for (unsigned i = 0; i < 8; ++i) payload |= static_cast<std::uint64_t>(f.data[i]) << (8 * i);
  const std::uint64_t mask = length >= 64 ? ~0ULL : ((1ULL << length) - 1);
  return (payload >> start) & mask;
}

void put_bits(io::CanFrame& f, unsigned start, unsigned length, std::uint64_t raw) {
  std::uint64_t payload = 0;
  for (unsigned i = 0; i < 8; ++i) payload |= static_cast<std::uint64_t>(f.data[i]) << (8 * i);
  const std::uint64_t mask = length >= 64 ? ~0ULL : ((1ULL << length) - 1);
  payload = (payload & ~(mask << start)) | ((raw & mask) << start);
  for (unsigned i = 0; i < 8; ++i) f.data[i] = static_cast<std::uint8_t>(payload >> (8 * i));
}

namespace {
io::CanFrame blank(std::uint32_t id, std::uint8_t dlc) {
  io::CanFrame f;
  f.id = id;
  f.extended = false;
  f.dlc = dlc;
  return f;
}
void seal(io::CanFrame& f) { f.data[7] = crc8(f.id, f.data.data()); }
}  // namespace

io::CanFrame encode_command(const CommandFrame& c, std::uint32_t id) {
  io::CanFrame f = blank(id, 8);
  put_bits(f, 0, 2, c.mode);
  put_bits(f, 4, 4, c.alive);
  put_bits(f, 8, 20, raw_unsigned(c.frequency_hz, 0.1, 20));
  put_bits(f, 28, 12, raw_signed(c.phase_deg, 0.1, 12));
  put_bits(f, 40, 12, raw_unsigned(c.amplitude_vpp, 0.25, 12));
  seal(f);
  return f;
}

io::CanFrame encode_aux(const AuxFrame& a, std::uint32_t id) {
  io::CanFrame f = blank(id, 8);
  put_bits(f, 4, 4, a.alive);
  put_bits(f, 8, 16, raw_signed(a.load_n, 0.001, 16));
  put_bits(f, 24, 16, raw_unsigned(a.frequency_slew_hz_per_s, 100.0, 16));
  put_bits(f, 40, 16, raw_unsigned(a.amplitude_slew_vpp_per_s, 10.0, 16));
  seal(f);
  return f;
}

namespace {
Reason check_frame(const io::CanFrame& f) {
  if (f.extended || f.dlc != 8) return Reason::wrong_length;
  if (crc8(f.id, f.data.data()) != f.data[7]) return Reason::bad_checksum;
  return Reason::none;
}
}  // namespace

Reason decode_command(const io::CanFrame& f, CommandFrame& out) {
  if (const Reason r = check_frame(f); r != Reason::none) return r;
  if (get_bits(f, 2, 2) != 0 || get_bits(f, 52, 4) != 0) return Reason::reserved_bits;
  out.mode = static_cast<std::uint8_t>(get_bits(f, 0, 2));
  out.alive = static_cast<std::uint8_t>(get_bits(f, 4, 4));
  out.frequency_hz = static_cast<double>(get_bits(f, 8, 20)) * 0.1;
  out.phase_deg = static_cast<double>(sign_extend(get_bits(f, 28, 12), 12)) * 0.1;
  out.amplitude_vpp = static_cast<double>(get_bits(f, 40, 12)) * 0.25;
  if (out.mode > 2) return Reason::unknown_command;
  return Reason::none;
}

Reason decode_aux(const io::CanFrame& f, AuxFrame& out) {
  if (const Reason r = check_frame(f); r != Reason::none) return r;
  if (get_bits(f, 0, 4) != 0) return Reason::reserved_bits;
  out.alive = static_cast<std::uint8_t>(get_bits(f, 4, 4));
  out.load_n = static_cast<double>(sign_extend(get_bits(f, 8, 16), 16)) * 0.001;
  out.frequency_slew_hz_per_s = static_cast<double>(get_bits(f, 24, 16)) * 100.0;
  out.amplitude_slew_vpp_per_s = static_cast<double>(get_bits(f, 40, 16)) * 10.0;
  return Reason::none;
}

Command to_command(const CommandFrame& c) {
  Command cmd;
  cmd.source = CommandSource::can;
  cmd.fields = Command::kAction | Command::kFrequency | Command::kAmplitude | Command::kPhase;
  cmd.action = c.mode == 0 ? Action::disable : c.mode == 1 ? Action::enable : Action::reset_fault;
  cmd.frequency_hz = c.frequency_hz;
  cmd.amplitude_vpp = c.amplitude_vpp;
  cmd.phase_deg = c.phase_deg;
  return cmd;
}

Command to_command(const AuxFrame& a) {
  Command cmd;
  cmd.source = CommandSource::can;
  cmd.fields = Command::kLoad | Command::kFrequencySlew | Command::kAmplitudeSlew;
  cmd.load_n = a.load_n;
  cmd.frequency_slew_hz_per_s = a.frequency_slew_hz_per_s;
  cmd.amplitude_slew_vpp_per_s = a.amplitude_slew_vpp_per_s;
  return cmd;
}

Reason AliveCounter::check(std::uint8_t alive, std::int64_t now_ns) const {
  if (!seen_ || now_ns - last_ns_ > kAliveResyncNs) return Reason::none;
  const unsigned delta = (static_cast<unsigned>(alive) - last_) & 0x0FU;
  return (delta >= 1 && delta <= 7) ? Reason::none : Reason::stale_alive_counter;
}

io::CanFrame encode_status(const Telemetry& t, const modbus::RejectSnapshot& r, std::uint8_t counter, std::uint32_t id) {
  io::CanFrame f = blank(id, 8);
  put_bits(f, 0, 2, static_cast<std::uint8_t>(t.state));
  put_bits(f, 2, 1, t.enable_line ? 1 : 0);
  put_bits(f, 3, 1, (t.state == AmpState::enabled && t.output.vpp > 0.0) ? 1 : 0);
  put_bits(f, 4, 1, t.at_setpoint ? 1 : 0);
  put_bits(f, 8, 8, static_cast<std::uint8_t>(t.fault));
  put_bits(f, 16, 8, static_cast<std::uint8_t>(r.last));
  put_bits(f, 24, 8, r.count & 0xFFU);
  put_bits(f, 32, 8, t.applied_commands & 0xFFU);
  put_bits(f, 40, 8, counter);
  return f;
}

io::CanFrame encode_motion(const Telemetry& t, std::uint32_t id) {
  io::CanFrame f = blank(id, 8);
  put_bits(f, 0, 32, raw_signed(t.speed_m_s * 1e6, 1.0, 32));
  put_bits(f, 32, 32, raw_signed(t.position_m * 1e6, 1.0, 32));
  return f;
}

io::CanFrame encode_drive(const Telemetry& t, std::uint32_t id) {
  io::CanFrame f = blank(id, 8);
  put_bits(f, 0, 16, raw_unsigned(t.tip_normal_um, 0.001, 16));
  put_bits(f, 16, 16, raw_unsigned(t.tip_tangential_um, 0.001, 16));
  put_bits(f, 32, 16, raw_unsigned(t.output.vpp, 0.1, 16));
  put_bits(f, 48, 16, raw_signed(t.output.phase_deg, 0.01, 16));
  return f;
}

io::CanFrame encode_loop_stats(const Telemetry& t, std::uint32_t id) {
  io::CanFrame f = blank(id, 8);
  put_bits(f, 0, 16, us(t.stats.lateness_p99_ns));
  put_bits(f, 16, 16, us(t.stats.lateness_p999_ns));
  put_bits(f, 32, 16, us(t.stats.lateness_max_ns));
  put_bits(f, 48, 16, std::min<std::uint64_t>(t.stats.overruns, 65535));
  return f;
}

io::CanFrame encode_output(const Telemetry& t, std::uint32_t id) {
  io::CanFrame f = blank(id, 8);
  put_bits(f, 0, 32, raw_unsigned(t.output.frequency_hz, 0.001, 32));
  put_bits(f, 32, 16, raw_signed(t.output.load_n, 0.001, 16));
  put_bits(f, 48, 16, us(t.stats.lateness_p50_ns));
  return f;
}

io::CanFrame encode_clock(const Telemetry& t, std::uint32_t id) {
  io::CanFrame f = blank(id, 8);
  const double ms = std::isfinite(t.sim_time_s) && t.sim_time_s > 0.0 ? std::floor(t.sim_time_s * 1e3) : 0.0;
  put_bits(f, 0, 32, static_cast<std::uint64_t>(std::fmod(ms, 4294967296.0)));
  put_bits(f, 32, 32, t.tick & 0xFFFFFFFFULL);
  return f;
}

io::CanFrame encode_heartbeat(std::uint32_t id) {
  io::CanFrame f = blank(id, 1);
  f.data[0] = 0x05;
  return f;
}

}  // namespace swum::emu::can
