#include "register_map.h"

#include <algorithm>
#include <cmath>

namespace swum::emu::modbus {

namespace {
constexpr std::array<std::uint16_t, 3> kHoldingU32{holding::kFrequency, holding::kFrequencySlew, holding::kAmplitudeSlew};
constexpr std::array<std::uint16_t, 8> kInputU32{input::kRejectCount, input::kAppliedCommands, input::kSpeed,
                                                 input::kPosition,    input::kFrequencyOut,    input::kTick,
                                                 input::kSimTime,     input::kOverruns};
constexpr std::array<std::uint16_t, 2> kInputU32More{input::kTickSpeed, input::kLastSequence};

bool contains(std::span<const std::uint16_t> list, std::uint16_t a) {
  return std::find(list.begin(), list.end(), a) != list.end();
}
// True when [address, address + quantity) cuts a 32-bit value in half.
bool splits(std::uint16_t address, std::uint16_t quantity, bool holding_table) {
  auto is_start = [&](std::uint16_t a) { return holding_table ? is_u32_start_holding(a) : is_u32_start_input(a); };
  const unsigned end = static_cast<unsigned>(address) + quantity;  // exclusive
  if (address > 0 && is_start(static_cast<std::uint16_t>(address - 1))) return true;  // starts on a low word
  if (end > 0 && is_start(static_cast<std::uint16_t>(end - 1))) return true;         // ends on a high word
  return false;
}

std::uint16_t sat_u16(double x) {
  if (!(x > 0.0)) return 0;
  if (x >= 65535.0) return 65535;
  return static_cast<std::uint16_t>(std::lround(x));
}
std::uint16_t sat_i16(double x) {
  if (!std::isfinite(x)) return 0;
  const double c = std::clamp(std::round(x), -32768.0, 32767.0);
  return static_cast<std::uint16_t>(static_cast<std::int16_t>(c));
}
std::uint32_t sat_u32(double x) {
  if (!(x > 0.0)) return 0;
  if (x >= 4294967295.0) return 0xFFFFFFFFU;
  return static_cast<std::uint32_t>(std::llround(x));
}
std::uint32_t sat_i32(double x) {
  if (!std::isfinite(x)) return 0;
  const double c = std::clamp(std::round(x), -2147483648.0, 2147483647.0);
  return static_cast<std::uint32_t>(static_cast<std::int32_t>(c));
}
void put32(std::span<std::uint16_t> r, std::uint16_t a, std::uint32_t v) {
  r[a] = static_cast<std::uint16_t>(v >> 16);
  r[a + 1U] = static_cast<std::uint16_t>(v & 0xFFFFU);
}
std::uint16_t us(std::uint64_t ns) { return sat_u16(static_cast<double>(ns) / 1000.0); }
}  // namespace

bool is_u32_start_holding(std::uint16_t a) { return contains(kHoldingU32, a); }
bool is_u32_start_input(std::uint16_t a) { return contains(kInputU32, a) || contains(kInputU32More, a); }

std::uint8_t parse_request(std::span<const std::uint8_t> pdu, Request& r, Reason* reason) {
  auto fail = [&](std::uint8_t ex, Reason why) {
    if (reason) *reason = why;
    return ex;
  };
  if (reason) *reason = Reason::none;
  if (pdu.empty()) return fail(kIllegalFunction, Reason::illegal_function);
  r.function = pdu[0];
  auto u16 = [&](std::size_t i) { return static_cast<std::uint16_t>((pdu[i] << 8) | pdu[i + 1]); };
  switch (r.function) {
    case kReadHoldingRegisters:
    case kReadInputRegisters:
      if (pdu.size() != 5) return fail(kIllegalDataValue, Reason::wrong_length);
      r.address = u16(1);
      r.quantity = u16(3);
      if (r.quantity < 1 || r.quantity > 125) return fail(kIllegalDataValue, Reason::wrong_length);
      return kNoException;
    case kWriteSingleRegister:
      if (pdu.size() != 5) return fail(kIllegalDataValue, Reason::wrong_length);
      r.address = u16(1);
      r.quantity = 1;
      r.values[0] = u16(3);
      return kNoException;
    case kWriteMultipleRegisters: {
      if (pdu.size() < 6) return fail(kIllegalDataValue, Reason::wrong_length);
      r.address = u16(1);
      r.quantity = u16(3);
      const std::size_t byte_count = pdu[5];
      if (r.quantity < 1 || r.quantity > 123 || byte_count != 2U * r.quantity || pdu.size() != 6 + byte_count)
        return fail(kIllegalDataValue, Reason::wrong_length);
      for (std::size_t i = 0; i < r.quantity; ++i) r.values[i] = u16(6 + 2 * i);
      return kNoException;
    }
    default:
      return fail(kIllegalFunction, Reason::illegal_function);
  }
}

Decision decide(const Request& r, const AmplifierLimits& limits) {
  Decision d;
  auto fail = [&](std::uint8_t ex, Reason why) {
    d.exception = ex;
    d.reason = why;
    d.has_command = false;
    return d;
  };
  const bool is_holding = r.function != kReadInputRegisters;
  const unsigned table = is_holding ? holding::kCount : input::kCount;
  if (static_cast<unsigned>(r.address) + r.quantity > table) return fail(kIllegalDataAddress, Reason::illegal_address);
  if (splits(r.address, r.quantity, is_holding)) return fail(kIllegalDataAddress, Reason::split_value);
  if (r.function == kReadHoldingRegisters || r.function == kReadInputRegisters) return d;

  // A write: gather the registers into one command.
  Command& c = d.command;
  c.source = CommandSource::modbus;
  auto reg = [&](unsigned a) { return r.values[a - r.address]; };
  auto reg32 = [&](unsigned a) { return (static_cast<std::uint32_t>(reg(a)) << 16) | reg(a + 1); };
  const unsigned end = static_cast<unsigned>(r.address) + r.quantity;
  for (unsigned a = r.address; a < end; ++a) {
    switch (a) {
      case holding::kCommand:
        if (reg(a) > kMaxAction) return fail(kIllegalDataValue, Reason::unknown_command);
        c.fields |= Command::kAction;
        c.action = static_cast<Action>(reg(a));
        break;
      case holding::kFrequency:
        c.fields |= Command::kFrequency;
        c.frequency_hz = reg32(a) * 1e-3;
        break;
      case holding::kAmplitude:
        c.fields |= Command::kAmplitude;
        c.amplitude_vpp = reg(a) * 0.1;
        break;
      case holding::kPhase:
        c.fields |= Command::kPhase;
        c.phase_deg = static_cast<std::int16_t>(reg(a)) * 0.01;
        break;
      case holding::kLoad:
        c.fields |= Command::kLoad;
        c.load_n = static_cast<std::int16_t>(reg(a)) * 1e-3;
        break;
      case holding::kFrequencySlew:
        c.fields |= Command::kFrequencySlew;
        c.frequency_slew_hz_per_s = reg32(a);
        break;
      case holding::kAmplitudeSlew:
        c.fields |= Command::kAmplitudeSlew;
        c.amplitude_slew_vpp_per_s = reg32(a);
        break;
      default:
        break;  // low words of 32-bit values
    }
  }
  const Reason why = validate(c, limits);
  if (why != Reason::none) return fail(kIllegalDataValue, why);
  d.has_command = true;
  return d;
}

void fill_holding(const Telemetry& t, std::span<std::uint16_t, holding::kCount> r) {
  r[holding::kCommand] = 0;
  put32(r, holding::kFrequency, sat_u32(t.setpoints.frequency_hz * 1e3));
  r[holding::kAmplitude] = sat_u16(t.setpoints.amplitude_vpp * 10.0);
  r[holding::kPhase] = sat_i16(t.setpoints.phase_deg * 100.0);
  r[holding::kLoad] = sat_i16(t.setpoints.load_n * 1e3);
  put32(r, holding::kFrequencySlew, sat_u32(t.setpoints.frequency_slew_hz_per_s));
  put32(r, holding::kAmplitudeSlew, sat_u32(t.setpoints.amplitude_slew_vpp_per_s));
}

void fill_input(const Telemetry& t, const RejectSnapshot& rejects, std::span<std::uint16_t, input::kCount> r) {
  const bool drive_on = t.state == AmpState::enabled && t.output.vpp > 0.0;
  r[input::kStatus] = static_cast<std::uint16_t>((t.state == AmpState::enabled ? 1U : 0U) |
                                                 (t.state == AmpState::fault ? 2U : 0U) | (t.enable_line ? 4U : 0U) |
                                                 (drive_on ? 8U : 0U) | (t.at_setpoint ? 16U : 0U));
  r[input::kState] = static_cast<std::uint16_t>(t.state);
  r[input::kFault] = static_cast<std::uint16_t>(t.fault);
  r[input::kLastReject] = static_cast<std::uint16_t>(rejects.last);
  put32(r, input::kRejectCount, static_cast<std::uint32_t>(rejects.count));
  put32(r, input::kAppliedCommands, static_cast<std::uint32_t>(t.applied_commands));
  put32(r, input::kSpeed, sat_i32(t.speed_m_s * 1e6));
  put32(r, input::kPosition, sat_i32(t.position_m * 1e6));
  r[input::kTipNormal] = sat_u16(t.tip_normal_um * 1e3);
  r[input::kTipTangential] = sat_u16(t.tip_tangential_um * 1e3);
  put32(r, input::kFrequencyOut, sat_u32(t.output.frequency_hz * 1e3));
  r[input::kAmplitudeOut] = sat_u16(t.output.vpp * 10.0);
  r[input::kPhaseOut] = sat_i16(t.output.phase_deg * 100.0);
  r[input::kLoadOut] = sat_i16(t.output.load_n * 1e3);
  put32(r, input::kTick, static_cast<std::uint32_t>(t.tick));
  put32(r, input::kSimTime, static_cast<std::uint32_t>(std::llround(t.sim_time_s * 1e3)));
  r[input::kLatenessP50] = us(t.stats.lateness_p50_ns);
  r[input::kLatenessP99] = us(t.stats.lateness_p99_ns);
  r[input::kLatenessP999] = us(t.stats.lateness_p999_ns);
  r[input::kLatenessMax] = us(t.stats.lateness_max_ns);
  r[input::kComputeP99] = us(t.stats.compute_p99_ns);
  r[input::kComputeMax] = us(t.stats.compute_max_ns);
  put32(r, input::kOverruns, static_cast<std::uint32_t>(t.stats.overruns));
  put32(r, input::kTickSpeed, sat_i32(t.tick_speed_m_s * 1e6));
  put32(r, input::kLastSequence, static_cast<std::uint32_t>(t.last_sequence));
}

}  // namespace swum::emu::modbus
