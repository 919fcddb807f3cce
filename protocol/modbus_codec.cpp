#include "modbus_codec.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace swum::protocol::modbus {

namespace {
constexpr std::array<std::uint16_t, 3> kHoldingU32{holding::kFrequency, holding::kFrequencySlew,
                                                   holding::kAmplitudeSlew};
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
  const unsigned end = static_cast<unsigned>(address) + quantity;                     // exclusive
  if (address > 0 && is_start(static_cast<std::uint16_t>(address - 1))) return true;  // starts on a low word
  if (end > 0 && is_start(static_cast<std::uint16_t>(end - 1))) return true;          // ends on a high word
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
std::uint16_t us(std::uint64_t ns) { return sat_u16(static_cast<double>(ns) / kTimingNsPerCount); }
}  // namespace

std::uint32_t get_u32(std::span<const std::uint16_t> r, std::size_t i) {
  return (static_cast<std::uint32_t>(r[i]) << 16) | r[i + 1];
}
void put_u32(std::span<std::uint16_t> r, std::size_t i, std::uint32_t v) {
  r[i] = static_cast<std::uint16_t>(v >> 16);
  r[i + 1] = static_cast<std::uint16_t>(v & 0xFFFFU);
}

bool is_u32_start_holding(std::uint16_t a) { return contains(kHoldingU32, a); }
bool is_u32_start_input(std::uint16_t a) { return contains(kInputU32, a) || contains(kInputU32More, a); }

MbapHeaderCheck check_mbap_header(std::span<const std::uint8_t> adu) {
  constexpr std::size_t kHeader = 7;  // transaction id (2), protocol id (2), length (2), unit id (1)
  if (adu.size() < kHeader + 1) return {};
  const unsigned protocol_id = (unsigned{adu[2]} << 8) | adu[3];
  const std::size_t announced = 6 + ((std::size_t{adu[4]} << 8) | adu[5]);  // the whole ADU
  if (protocol_id != 0 || announced < adu.size() || announced > kTcpMaxAduBytes) return {};
  return {true, announced - adu.size()};
}

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
    default: return fail(kIllegalFunction, Reason::illegal_function);
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
        c.frequency_hz = reg32(a) * kFrequencyScale.unit_per_count;
        break;
      case holding::kAmplitude:
        c.fields |= Command::kAmplitude;
        c.amplitude_v = reg(a) * kAmplitudeScale.unit_per_count;
        break;
      case holding::kPhase:
        c.fields |= Command::kPhase;
        c.phase_deg = static_cast<std::int16_t>(reg(a)) * kPhaseScale.unit_per_count;
        break;
      case holding::kLoad:
        c.fields |= Command::kLoad;
        c.load_n = static_cast<std::int16_t>(reg(a)) * kLoadScale.unit_per_count;
        break;
      case holding::kFrequencySlew:
        c.fields |= Command::kFrequencySlew;
        c.frequency_slew_hz_per_s = reg32(a) * kSlewScale.unit_per_count;
        break;
      case holding::kAmplitudeSlew:
        c.fields |= Command::kAmplitudeSlew;
        c.amplitude_slew_v_per_s = reg32(a) * kSlewScale.unit_per_count;
        break;
      case holding::kAdvance: d.advance_ticks = reg(a); break;
      default: break;  // low words of 32-bit values
    }
  }
  const Reason why = validate(c, limits);
  if (why != Reason::none) return fail(kIllegalDataValue, why);
  // A write of the advance register alone is a step, not a command (it does not feed the watchdog).
  d.has_command = c.fields != 0;
  return d;
}

void fill_holding(const Telemetry& t, std::span<std::uint16_t, holding::kCount> r) {
  r[holding::kCommand] = 0;
  put_u32(r, holding::kFrequency, sat_u32(t.setpoints.frequency_hz * kFrequencyScale.count_per_unit));
  r[holding::kAmplitude] = sat_u16(t.setpoints.amplitude_v * kAmplitudeScale.count_per_unit);
  r[holding::kPhase] = sat_i16(t.setpoints.phase_deg * kPhaseScale.count_per_unit);
  r[holding::kLoad] = sat_i16(t.setpoints.load_n * kLoadScale.count_per_unit);
  put_u32(r, holding::kFrequencySlew, sat_u32(t.setpoints.frequency_slew_hz_per_s * kSlewScale.count_per_unit));
  put_u32(r, holding::kAmplitudeSlew, sat_u32(t.setpoints.amplitude_slew_v_per_s * kSlewScale.count_per_unit));
  r[holding::kAdvance] = 0;
}

void fill_input(const Telemetry& t, const RejectSnapshot& rejects, std::span<std::uint16_t, input::kCount> r) {
  r[input::kStatus] = static_cast<std::uint16_t>(
      (t.state == AmpState::enabled ? kStatusEnabled : 0U) | (t.state == AmpState::fault ? kStatusFault : 0U) |
      (t.enable_line ? kStatusEnableLine : 0U) | (drive_on(t) ? kStatusDriveOn : 0U) |
      (t.at_setpoint ? kStatusAtSetpoint : 0U));
  r[input::kState] = static_cast<std::uint16_t>(t.state);
  r[input::kFault] = static_cast<std::uint16_t>(t.fault);
  r[input::kLastReject] = static_cast<std::uint16_t>(rejects.last);
  put_u32(r, input::kRejectCount, static_cast<std::uint32_t>(rejects.count));
  put_u32(r, input::kAppliedCommands, static_cast<std::uint32_t>(t.applied_commands));
  put_u32(r, input::kSpeed, sat_i32(t.speed_m_s * kMicroScale.count_per_unit));
  put_u32(r, input::kPosition, sat_i32(t.position_m * kMicroScale.count_per_unit));
  r[input::kTipNormal] = sat_u16(t.tip_normal_um * kTipScale.count_per_unit);
  r[input::kTipTangential] = sat_u16(t.tip_tangential_um * kTipScale.count_per_unit);
  put_u32(r, input::kFrequencyOut, sat_u32(t.output.frequency_hz * kFrequencyScale.count_per_unit));
  r[input::kAmplitudeOut] = sat_u16(t.output.amplitude_v * kAmplitudeScale.count_per_unit);
  r[input::kPhaseOut] = sat_i16(t.output.phase_deg * kPhaseScale.count_per_unit);
  r[input::kLoadOut] = sat_i16(t.output.load_n * kLoadScale.count_per_unit);
  put_u32(r, input::kTick, static_cast<std::uint32_t>(t.tick));
  put_u32(r, input::kSimTime, static_cast<std::uint32_t>(std::llround(t.sim_time_s * kSimTimeScale.count_per_unit)));
  r[input::kLatenessP50] = us(t.stats.lateness_p50_ns);
  r[input::kLatenessP99] = us(t.stats.lateness_p99_ns);
  r[input::kLatenessP999] = us(t.stats.lateness_p999_ns);
  r[input::kLatenessMax] = us(t.stats.lateness_max_ns);
  r[input::kComputeP99] = us(t.stats.compute_p99_ns);
  r[input::kComputeMax] = us(t.stats.compute_max_ns);
  put_u32(r, input::kOverruns, static_cast<std::uint32_t>(t.stats.overruns));
  put_u32(r, input::kTickSpeed, sat_i32(t.tick_speed_m_s * kMicroScale.count_per_unit));
  put_u32(r, input::kLastSequence, static_cast<std::uint32_t>(t.last_sequence));
  r[input::kClock] = t.external_clock ? 1U : 0U;
  const ElectricalValues& e = t.electrical;
  r[input::kCurrentA] = sat_u16(e.current_a_a * kCurrentScale.count_per_unit);
  r[input::kCurrentB] = sat_u16(e.current_b_a * kCurrentScale.count_per_unit);
  r[input::kPhaseA] = sat_i16(e.phase_a_deg * kPhaseScale.count_per_unit);
  r[input::kPhaseB] = sat_i16(e.phase_b_deg * kPhaseScale.count_per_unit);
  r[input::kMotionalPhaseA] = sat_i16(e.motional_phase_a_deg * kPhaseScale.count_per_unit);
  r[input::kMotionalPhaseB] = sat_i16(e.motional_phase_b_deg * kPhaseScale.count_per_unit);
  r[input::kPowerA] = sat_i16(e.power_a_w * kPowerScale.count_per_unit);
  r[input::kPowerB] = sat_i16(e.power_b_w * kPowerScale.count_per_unit);
  r[input::kStatorTemperature] = sat_i16(t.stator_temperature_c * kTemperatureScale.count_per_unit);
  const AmplifierOutputValues& o = t.amplifier_output;
  r[input::kAmplifierCurrentA] = sat_u16(o.current_a_a * kCurrentScale.count_per_unit);
  r[input::kAmplifierCurrentB] = sat_u16(o.current_b_a * kCurrentScale.count_per_unit);
  r[input::kAmplifierPhaseA] = sat_i16(o.current_phase_a_deg * kPhaseScale.count_per_unit);
  r[input::kAmplifierPhaseB] = sat_i16(o.current_phase_b_deg * kPhaseScale.count_per_unit);
  r[input::kTerminalAmplitudeA] = sat_u16(o.terminal_amplitude_a_v * kAmplitudeScale.count_per_unit);
  r[input::kTerminalAmplitudeB] = sat_u16(o.terminal_amplitude_b_v * kAmplitudeScale.count_per_unit);
}

namespace {
// A register value that must fit [lo, hi] as it stands (the controller does not saturate: a set-point
// that does not fit is an error, never a silently different command).
bool fits(double counts, double lo, double hi) { return std::isfinite(counts) && counts >= lo && counts <= hi; }
std::string does_not_fit(const char* what, double counts, double lo, double hi) {
  return std::string(what) + " " + std::to_string(counts) + " does not fit the register (" + std::to_string(lo) + ".." +
         std::to_string(hi) + ")";
}
std::uint16_t to_u16_bits(double counts) {
  return static_cast<std::uint16_t>(static_cast<std::int32_t>(std::lround(counts)) & 0xFFFF);
}
}  // namespace

std::string encode_drive_write(double frequency_hz, double amplitude_v, double phase_deg, double load_n,
                               std::span<std::uint16_t, kDriveWriteCount> r) {
  const double frequency_counts = std::round(frequency_hz * kFrequencyScale.count_per_unit);
  if (!fits(frequency_counts, 0.0, 4294967295.0)) {
    return "frequency " + std::to_string(frequency_hz) + " Hz does not fit the register";
  }
  struct Field {
    double counts;
    double lo, hi;
    const char* what;
  };
  const Field fields[] = {
      {amplitude_v * kAmplitudeScale.count_per_unit, 0.0, 65535.0, "amplitude (0.1 V)"},
      {phase_deg * kPhaseScale.count_per_unit, -32768.0, 32767.0, "phase (0.01 deg)"},
      {load_n * kLoadScale.count_per_unit, -32768.0, 32767.0, "load (mN)"},
  };
  put_u32(r, holding::kFrequency - holding::kFrequency, static_cast<std::uint32_t>(frequency_counts));
  std::size_t i = holding::kAmplitude - holding::kFrequency;
  for (const Field& f : fields) {
    if (!fits(f.counts, f.lo, f.hi)) return does_not_fit(f.what, f.counts, f.lo, f.hi);
    r[i++] = to_u16_bits(f.counts);
  }
  return {};
}

std::string encode_slew_write(double frequency_hz_per_s, double amplitude_v_per_s,
                              std::span<std::uint16_t, kSlewWriteCount> r) {
  for (double v : {frequency_hz_per_s, amplitude_v_per_s}) {
    if (!fits(v * kSlewScale.count_per_unit, 0.0, 4294967295.0)) return "slew limit out of range";
  }
  auto counts = [](double v) {
    const double c = v * kSlewScale.count_per_unit;
    return c > 0.0 ? std::max<std::uint32_t>(1, static_cast<std::uint32_t>(c)) : 0U;
  };
  put_u32(r, 0, counts(frequency_hz_per_s));
  put_u32(r, holding::kAmplitudeSlew - holding::kFrequencySlew, counts(amplitude_v_per_s));
  return {};
}

std::string encode_advance(std::uint64_t ticks, std::uint16_t& register_value) {
  if (ticks < 1 || ticks > 65535)
    return "advance of " + std::to_string(ticks) + " ticks does not fit the register (1..65535)";
  register_value = static_cast<std::uint16_t>(ticks);
  return {};
}

std::string encode_step_write(Action action, const AmplifierSetpoints& s, std::uint64_t ticks,
                              std::span<std::uint16_t, holding::kCount> r) {
  r[holding::kCommand] = command_code(action);
  std::string problem = encode_drive_write(s.frequency_hz, s.amplitude_v, s.phase_deg, s.load_n,
                                           r.subspan<holding::kFrequency, kDriveWriteCount>());
  if (problem.empty()) {
    problem = encode_slew_write(s.frequency_slew_hz_per_s, s.amplitude_slew_v_per_s,
                                r.subspan<holding::kFrequencySlew, kSlewWriteCount>());
  }
  if (problem.empty()) problem = encode_advance(ticks, r[holding::kAdvance]);
  return problem;
}

InputImage decode_input(std::span<const std::uint16_t, input::kCount> r) {
  InputImage image;
  Telemetry& t = image.telemetry;
  auto i32 = [&](std::uint16_t a) { return static_cast<std::int32_t>(get_u32(r, a)); };
  auto i16 = [&](std::uint16_t a) { return static_cast<std::int16_t>(r[a]); };
  auto ns = [&](std::uint16_t a) { return static_cast<std::uint64_t>(r[a] * kTimingNsPerCount); };
  image.status_bits = r[input::kStatus];
  image.state_code = r[input::kState];
  image.fault_code = r[input::kFault];
  image.last_reject_code = r[input::kLastReject];
  constexpr double kMillimetresPerMicrometre = 1e-3;  // speed counts are um/s, position counts um
  image.speed_mm_s = i32(input::kSpeed) * kMillimetresPerMicrometre;
  image.position_mm = i32(input::kPosition) * kMillimetresPerMicrometre;
  t.enable_line = (image.status_bits & kStatusEnableLine) != 0;
  t.at_setpoint = (image.status_bits & kStatusAtSetpoint) != 0;
  t.state = static_cast<AmpState>(r[input::kState]);
  t.fault = static_cast<FaultCode>(r[input::kFault]);
  image.rejects.last = static_cast<Reason>(r[input::kLastReject]);
  image.rejects.count = get_u32(r, input::kRejectCount);
  t.applied_commands = get_u32(r, input::kAppliedCommands);
  t.speed_m_s = i32(input::kSpeed) * kMicroScale.unit_per_count;
  t.position_m = i32(input::kPosition) * kMicroScale.unit_per_count;
  t.tip_normal_um = r[input::kTipNormal] * kTipScale.unit_per_count;
  t.tip_tangential_um = r[input::kTipTangential] * kTipScale.unit_per_count;
  t.output.frequency_hz = get_u32(r, input::kFrequencyOut) * kFrequencyScale.unit_per_count;
  t.output.amplitude_v = r[input::kAmplitudeOut] * kAmplitudeScale.unit_per_count;
  t.output.phase_deg = i16(input::kPhaseOut) * kPhaseScale.unit_per_count;
  t.output.load_n = i16(input::kLoadOut) * kLoadScale.unit_per_count;
  t.tick = get_u32(r, input::kTick);
  t.sim_time_s = get_u32(r, input::kSimTime) * kSimTimeScale.unit_per_count;
  t.stats.lateness_p50_ns = ns(input::kLatenessP50);
  t.stats.lateness_p99_ns = ns(input::kLatenessP99);
  t.stats.lateness_p999_ns = ns(input::kLatenessP999);
  t.stats.lateness_max_ns = ns(input::kLatenessMax);
  t.stats.compute_p99_ns = ns(input::kComputeP99);
  t.stats.compute_max_ns = ns(input::kComputeMax);
  t.stats.overruns = get_u32(r, input::kOverruns);
  t.tick_speed_m_s = i32(input::kTickSpeed) * kMicroScale.unit_per_count;
  t.last_sequence = get_u32(r, input::kLastSequence);
  t.external_clock = r[input::kClock] == 1U;
  ElectricalValues& e = t.electrical;
  e.current_a_a = r[input::kCurrentA] * kCurrentScale.unit_per_count;
  e.current_b_a = r[input::kCurrentB] * kCurrentScale.unit_per_count;
  e.phase_a_deg = i16(input::kPhaseA) * kPhaseScale.unit_per_count;
  e.phase_b_deg = i16(input::kPhaseB) * kPhaseScale.unit_per_count;
  e.motional_phase_a_deg = i16(input::kMotionalPhaseA) * kPhaseScale.unit_per_count;
  e.motional_phase_b_deg = i16(input::kMotionalPhaseB) * kPhaseScale.unit_per_count;
  e.power_a_w = i16(input::kPowerA) * kPowerScale.unit_per_count;
  e.power_b_w = i16(input::kPowerB) * kPowerScale.unit_per_count;
  t.stator_temperature_c = i16(input::kStatorTemperature) * kTemperatureScale.unit_per_count;
  AmplifierOutputValues& o = t.amplifier_output;
  o.current_a_a = r[input::kAmplifierCurrentA] * kCurrentScale.unit_per_count;
  o.current_b_a = r[input::kAmplifierCurrentB] * kCurrentScale.unit_per_count;
  o.current_phase_a_deg = i16(input::kAmplifierPhaseA) * kPhaseScale.unit_per_count;
  o.current_phase_b_deg = i16(input::kAmplifierPhaseB) * kPhaseScale.unit_per_count;
  o.terminal_amplitude_a_v = r[input::kTerminalAmplitudeA] * kAmplitudeScale.unit_per_count;
  o.terminal_amplitude_b_v = r[input::kTerminalAmplitudeB] * kAmplitudeScale.unit_per_count;
  return image;
}

}  // namespace swum::protocol::modbus
