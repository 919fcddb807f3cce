#include "can_telemetry_decode.h"

#include "can_protocol.h"

namespace swum::emu::can {
namespace {
double signed_value(std::uint64_t raw, unsigned bits, double factor) {
  const std::uint64_t sign = 1ULL << (bits - 1);
  return static_cast<double>(static_cast<std::int64_t>((raw ^ sign) - sign)) * factor;
}
bool full(const io::CanFrame& f) { return !f.extended && f.dlc == 8; }
}  // namespace

bool decode_status(const io::CanFrame& f, StatusFields& out) {
  if (!full(f)) return false;
  out.state = static_cast<std::uint8_t>(get_bits(f, 0, 2));
  out.enable_line = get_bits(f, 2, 1) != 0;
  out.drive_on = get_bits(f, 3, 1) != 0;
  out.at_setpoint = get_bits(f, 4, 1) != 0;
  out.fault = static_cast<std::uint8_t>(get_bits(f, 8, 8));
  out.last_reject = static_cast<std::uint8_t>(get_bits(f, 16, 8));
  out.reject_count = static_cast<std::uint8_t>(get_bits(f, 24, 8));
  out.applied_count = static_cast<std::uint8_t>(get_bits(f, 32, 8));
  out.status_counter = static_cast<std::uint8_t>(get_bits(f, 40, 8));
  return true;
}

bool decode_motion(const io::CanFrame& f, MotionFields& out) {
  if (!full(f)) return false;
  out.speed_mm_s = signed_value(get_bits(f, 0, 32), 32, 1e-3);  // raw um/s
  out.position_mm = signed_value(get_bits(f, 32, 32), 32, 1e-3);
  return true;
}

bool decode_drive(const io::CanFrame& f, DriveFields& out) {
  if (!full(f)) return false;
  out.tip_normal_um = static_cast<double>(get_bits(f, 0, 16)) * 1e-3;
  out.tip_tangential_um = static_cast<double>(get_bits(f, 16, 16)) * 1e-3;
  out.vpp = static_cast<double>(get_bits(f, 32, 16)) * 0.1;
  out.phase_deg = signed_value(get_bits(f, 48, 16), 16, 0.01);
  return true;
}

bool decode_loop_stats(const io::CanFrame& f, LoopStatsFields& out) {
  if (!full(f)) return false;
  out.lateness_p99_us = static_cast<double>(get_bits(f, 0, 16));
  out.lateness_p999_us = static_cast<double>(get_bits(f, 16, 16));
  out.lateness_max_us = static_cast<double>(get_bits(f, 32, 16));
  out.overruns = static_cast<std::uint32_t>(get_bits(f, 48, 16));
  return true;
}

bool decode_output(const io::CanFrame& f, OutputFields& out) {
  if (!full(f)) return false;
  out.frequency_hz = static_cast<double>(get_bits(f, 0, 32)) * 1e-3;
  out.load_n = signed_value(get_bits(f, 32, 16), 16, 1e-3);
  out.lateness_p50_us = static_cast<double>(get_bits(f, 48, 16));
  return true;
}

bool decode_clock(const io::CanFrame& f, ClockFields& out) {
  if (!full(f)) return false;
  out.sim_time_s = static_cast<double>(get_bits(f, 0, 32)) * 1e-3;
  out.tick = static_cast<std::uint32_t>(get_bits(f, 32, 32));
  return true;
}

}  // namespace swum::emu::can
