// Both directions of each codec meet: what a controller encodes, the device decodes to the same
// command; what the device encodes, a controller decodes to the same values, to the wire's
// resolution. The host tool and swum-emu run exactly these functions.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "can_codec.h"
#include "can_telemetry_decode.h"
#include "modbus_codec.h"

namespace swum::protocol {
namespace {

// The PDU of a write-multiple request of `values` at `address` (what libmodbus sends).
std::vector<std::uint8_t> write_pdu(std::uint16_t address, std::span<const std::uint16_t> values) {
  std::vector<std::uint8_t> pdu{modbus::kWriteMultipleRegisters,          static_cast<std::uint8_t>(address >> 8),
                                static_cast<std::uint8_t>(address),       0,
                                static_cast<std::uint8_t>(values.size()), static_cast<std::uint8_t>(2 * values.size())};
  for (const std::uint16_t v : values) {
    pdu.push_back(static_cast<std::uint8_t>(v >> 8));
    pdu.push_back(static_cast<std::uint8_t>(v));
  }
  return pdu;
}

modbus::Decision device_decides(std::uint16_t address, std::span<const std::uint16_t> values) {
  modbus::Request request;
  Reason why = Reason::none;
  const std::vector<std::uint8_t> pdu = write_pdu(address, values);
  EXPECT_EQ(modbus::parse_request(pdu, request, &why), modbus::kNoException);
  return modbus::decide(request, AmplifierLimits{});
}

TEST(ModbusScales, BothDirectionsAreReciprocal) {
  for (const modbus::Scale s :
       {modbus::kFrequencyScale, modbus::kAmplitudeScale, modbus::kPhaseScale, modbus::kLoadScale, modbus::kSlewScale,
        modbus::kMicroScale, modbus::kTipScale, modbus::kSimTimeScale, modbus::kCurrentScale, modbus::kPowerScale,
        modbus::kTemperatureScale}) {
    EXPECT_NEAR(s.unit_per_count * s.count_per_unit, 1.0, 1e-15) << s.unit_per_count;
  }
}

TEST(ModbusRoundTrip, DriveWriteBecomesTheSameCommandOnTheDevice) {
  struct Case {
    double frequency_hz, amplitude_v, phase_deg, load_n;
  };
  for (const Case c : {Case{40123.456, 400.0, -90.0, 0.0}, Case{30000.0, 0.0, 180.0, -30.0},
                       Case{49999.999, 599.9, 0.01, 2.345}, Case{40400.0, 137.5, 90.0, -0.001}}) {
    std::array<std::uint16_t, modbus::kDriveWriteCount> r{};
    ASSERT_EQ(modbus::encode_drive_write(c.frequency_hz, c.amplitude_v, c.phase_deg, c.load_n, r), "");
    const modbus::Decision d = device_decides(modbus::holding::kFrequency, r);
    ASSERT_EQ(d.exception, modbus::kNoException) << to_string(d.reason);
    ASSERT_TRUE(d.has_command);
    EXPECT_EQ(d.command.fields, Command::kFrequency | Command::kAmplitude | Command::kPhase | Command::kLoad);
    EXPECT_NEAR(d.command.frequency_hz, c.frequency_hz, 0.5e-3);
    EXPECT_NEAR(d.command.amplitude_v, c.amplitude_v, 0.05);
    EXPECT_NEAR(d.command.phase_deg, c.phase_deg, 0.005);
    EXPECT_NEAR(d.command.load_n, c.load_n, 0.5e-3);
  }
}

TEST(ModbusRoundTrip, DriveWriteRefusesWhatDoesNotFitInsteadOfWrapping) {
  std::array<std::uint16_t, modbus::kDriveWriteCount> r{};
  EXPECT_EQ(modbus::encode_drive_write(-1.0, 10.0, 0.0, 0.0, r), "frequency -1.000000 Hz does not fit the register");
  EXPECT_NE(modbus::encode_drive_write(40000.0, 6553.6, 0.0, 0.0, r).find("amplitude (0.1 V) 65536"),
            std::string::npos);
  EXPECT_NE(modbus::encode_drive_write(40000.0, 10.0, 327.68, 0.0, r).find("phase (0.01 deg)"), std::string::npos);
  EXPECT_NE(modbus::encode_drive_write(40000.0, 10.0, 0.0, -32.769, r).find("load (mN)"), std::string::npos);
  EXPECT_NE(modbus::encode_drive_write(40000.0, std::nan(""), 0.0, 0.0, r), "");
}

TEST(ModbusRoundTrip, SlewWriteRoundsDownButNeverToUnlimited) {
  std::array<std::uint16_t, modbus::kSlewWriteCount> r{};
  ASSERT_EQ(modbus::encode_slew_write(1234.9, 0.4, r), "");
  const modbus::Decision d = device_decides(modbus::holding::kFrequencySlew, r);
  ASSERT_TRUE(d.has_command) << to_string(d.reason);
  EXPECT_EQ(d.command.frequency_slew_hz_per_s, 1234.0);
  EXPECT_EQ(d.command.amplitude_slew_v_per_s, 1.0);  // 0.4 would round to 0 = unlimited
  ASSERT_EQ(modbus::encode_slew_write(0.0, 0.0, r), "");
  EXPECT_EQ(device_decides(modbus::holding::kFrequencySlew, r).command.frequency_slew_hz_per_s, 0.0);
  EXPECT_EQ(modbus::encode_slew_write(-1.0, 0.0, r), "slew limit out of range");
}

TEST(ModbusRoundTrip, CommandCodesAreTheDevicesActions) {
  for (const Action a : {Action::none, Action::enable, Action::disable, Action::reset_fault}) {
    const std::array<std::uint16_t, 1> r{modbus::command_code(a)};
    const modbus::Decision d = device_decides(modbus::holding::kCommand, r);
    ASSERT_TRUE(d.has_command);
    EXPECT_EQ(d.command.action, a);
  }
}

TEST(ModbusRoundTrip, StepWriteIsOneCommandAndTheTicksToRun) {
  AmplifierSetpoints s;
  s.frequency_hz = 40123.456;
  s.amplitude_v = 137.5;
  s.phase_deg = -90.0;
  s.frequency_slew_hz_per_s = 1000.0;
  s.amplitude_slew_v_per_s = 0.0;
  std::array<std::uint16_t, modbus::holding::kCount> r{};
  ASSERT_EQ(modbus::encode_step_write(Action::enable, s, 10, r), "");
  const modbus::Decision d = device_decides(modbus::holding::kCommand, r);
  ASSERT_EQ(d.exception, modbus::kNoException) << to_string(d.reason);
  ASSERT_TRUE(d.has_command);
  EXPECT_EQ(d.advance_ticks, 10);
  EXPECT_EQ(d.command.action, Action::enable);
  EXPECT_NEAR(d.command.frequency_hz, s.frequency_hz, 0.5e-3);
  EXPECT_NEAR(d.command.amplitude_v, s.amplitude_v, 0.05);
  EXPECT_NEAR(d.command.phase_deg, s.phase_deg, 0.005);
  EXPECT_EQ(d.command.frequency_slew_hz_per_s, 1000.0);
  EXPECT_EQ(d.command.amplitude_slew_v_per_s, 0.0);
  EXPECT_NE(modbus::encode_step_write(Action::none, s, 0, r).find("advance of 0 ticks"), std::string::npos);
  EXPECT_NE(modbus::encode_step_write(Action::none, s, 65536, r).find("65536"), std::string::npos);
  s.amplitude_v = 6553.6;
  EXPECT_NE(modbus::encode_step_write(Action::none, s, 10, r).find("amplitude"), std::string::npos);
}

Telemetry sample() {
  Telemetry t;
  t.tick = 123456;
  t.sim_time_s = 12.345;
  t.state = AmpState::enabled;
  t.fault = FaultCode::none;
  t.enable_line = true;
  t.at_setpoint = false;
  t.output = {412.3, 40321.5, -87.65, -1.234};
  t.speed_m_s = -0.123456;
  t.tick_speed_m_s = 0.0987;
  t.position_m = 1.5;
  t.tip_normal_um = 1.234;
  t.tip_tangential_um = 2.5;
  t.applied_commands = 77;
  t.last_sequence = 99;
  t.stats.overruns = 5;
  t.stats.lateness_p50_ns = 3000;
  t.stats.lateness_p99_ns = 14000;
  t.stats.lateness_max_ns = 1'300'000;
  return t;
}

TEST(ModbusRoundTrip, InputRegistersDecodeToWhatTheDeviceFilled) {
  const Telemetry t = sample();
  std::array<std::uint16_t, modbus::input::kCount> r{};
  modbus::fill_input(t, RejectSnapshot{Reason::stale_alive_counter, 70000}, r);
  const modbus::InputImage back = modbus::decode_input(r);
  const Telemetry& d = back.telemetry;
  EXPECT_EQ(back.status_bits, kStatusEnabled | kStatusEnableLine | kStatusDriveOn);
  EXPECT_EQ(d.state, t.state);
  EXPECT_EQ(d.enable_line, t.enable_line);
  EXPECT_EQ(d.at_setpoint, t.at_setpoint);
  EXPECT_EQ(back.rejects.last, Reason::stale_alive_counter);
  EXPECT_EQ(back.rejects.count, 70000u);  // 32 bits over two registers, high word first
  EXPECT_EQ(d.applied_commands, 77u);
  EXPECT_EQ(d.tick, 123456u);
  EXPECT_NEAR(d.sim_time_s, 12.345, 0.5e-3);
  EXPECT_NEAR(d.speed_m_s, t.speed_m_s, 0.5e-6);
  EXPECT_NEAR(d.tick_speed_m_s, t.tick_speed_m_s, 0.5e-6);
  EXPECT_NEAR(d.position_m, t.position_m, 0.5e-6);
  EXPECT_NEAR(d.tip_normal_um, t.tip_normal_um, 0.5e-3);
  EXPECT_NEAR(d.tip_tangential_um, t.tip_tangential_um, 0.5e-3);
  EXPECT_NEAR(d.output.frequency_hz, t.output.frequency_hz, 0.5e-3);
  EXPECT_NEAR(d.output.amplitude_v, t.output.amplitude_v, 0.05);
  EXPECT_NEAR(d.output.phase_deg, t.output.phase_deg, 0.005);
  EXPECT_NEAR(d.output.load_n, t.output.load_n, 0.5e-3);
  EXPECT_EQ(d.stats.lateness_p50_ns, 3000u);
  EXPECT_EQ(d.stats.lateness_p99_ns, 14000u);
  EXPECT_EQ(d.stats.lateness_max_ns, 1'300'000u);
  EXPECT_EQ(d.stats.overruns, 5u);
  EXPECT_EQ(d.last_sequence, 99u);
}

TEST(ModbusRoundTrip, ControllerUnitsMatchTheCanDecoderAndUnknownCodesStayAsSent) {
  std::array<std::uint16_t, modbus::input::kCount> r{};
  modbus::put_u32(r, modbus::input::kSpeed, static_cast<std::uint32_t>(-123457));  // um/s
  modbus::put_u32(r, modbus::input::kPosition, 1500001);                           // um
  r[modbus::input::kState] = 258;  // no such state: must not read as 2 (fault)
  r[modbus::input::kLastReject] = 300;
  const modbus::InputImage image = modbus::decode_input(r);
  // Bit for bit what the CAN decoder gives for the same counts (both compute counts * 1e-3).
  CanFrame motion;
  motion.dlc = 8;
  can::put_raw(motion, can::signals::kMotionSpeed, static_cast<std::uint32_t>(-123457));
  can::put_raw(motion, can::signals::kMotionPosition, 1500001);
  can::MotionFields m;
  ASSERT_EQ(can::decode_motion(motion, m), Reason::none);
  EXPECT_EQ(image.speed_mm_s, m.speed_mm_s);
  EXPECT_EQ(image.position_mm, m.position_mm);
  EXPECT_EQ(image.speed_mm_s, -123457 * 1e-3);
  EXPECT_EQ(image.state_code, 258);
  EXPECT_EQ(image.last_reject_code, 300);
}

TEST(CanRoundTrip, CommandAndAuxFramesDecodeToWhatWasEncoded) {
  const can::Ids ids = can::ids_for_node(5);
  can::CommandFrame c;
  c.mode = can::mode::kEnable;
  c.alive = can::next_alive(15);
  c.frequency_hz = 40321.7;
  c.phase_deg = -89.9;
  c.amplitude_v = 412.25;
  can::CommandFrame back;
  ASSERT_EQ(can::decode_command(can::encode_command(c, ids.command), back), Reason::none);
  EXPECT_EQ(back.mode, c.mode);
  EXPECT_EQ(back.alive, 0);  // 15 + 1 wraps in 4 bits
  EXPECT_NEAR(back.frequency_hz, c.frequency_hz, 0.05);
  EXPECT_NEAR(back.phase_deg, c.phase_deg, 0.05);
  EXPECT_NEAR(back.amplitude_v, c.amplitude_v, 0.125);
  EXPECT_EQ(can::to_command(back).action, Action::enable);

  can::AuxFrame a;
  a.alive = 3;
  a.load_n = -2.345;
  a.frequency_slew_hz_per_s = 1'000'000.0;
  a.amplitude_slew_v_per_s = 100'000.0;
  can::AuxFrame aux_back;
  ASSERT_EQ(can::decode_aux(can::encode_aux(a, ids.aux), aux_back), Reason::none);
  EXPECT_NEAR(aux_back.load_n, a.load_n, 0.5e-3);
  // 16 bits of 100 Hz/s and 10 V/s: saturate at 6 553 500 Hz/s and 655 350 V/s.
  EXPECT_EQ(aux_back.frequency_slew_hz_per_s, 1'000'000.0);
  EXPECT_EQ(aux_back.amplitude_slew_v_per_s, 100'000.0);
}

TEST(CanRoundTrip, TelemetryFramesDecodeToWhatTheDeviceEncoded) {
  const Telemetry t = sample();
  const can::Ids ids = can::ids_for_node(1);
  can::StatusFields s;
  ASSERT_EQ(can::decode_status(can::encode_status(t, RejectSnapshot{Reason::bad_checksum, 258}, 17, ids.status), s),
            Reason::none);
  EXPECT_EQ(s.state, static_cast<std::uint8_t>(AmpState::enabled));
  EXPECT_TRUE(s.drive_on);
  EXPECT_EQ(s.last_reject, static_cast<std::uint8_t>(Reason::bad_checksum));
  EXPECT_EQ(s.reject_count, 258 % 256);
  EXPECT_EQ(s.status_counter, 17);
  can::MotionFields m;
  ASSERT_EQ(can::decode_motion(can::encode_motion(t, ids.motion), m), Reason::none);
  EXPECT_NEAR(m.speed_mm_s, t.speed_m_s * 1e3, 0.5e-3);
  EXPECT_NEAR(m.position_mm, t.position_m * 1e3, 0.5e-3);
  can::OutputFields o;
  ASSERT_EQ(can::decode_output(can::encode_output(t, ids.output), o), Reason::none);
  EXPECT_NEAR(o.frequency_hz, t.output.frequency_hz, 0.5e-3);
  EXPECT_NEAR(o.load_n, t.output.load_n, 0.5e-3);
  EXPECT_EQ(o.lateness_p50_us, 3.0);
  can::ClockFields k;
  ASSERT_EQ(can::decode_clock(can::encode_clock(t, ids.clock), k), Reason::none);
  EXPECT_NEAR(k.sim_time_s, 12.345, 1e-3);
  EXPECT_EQ(k.tick, 123456u);
}

// The electrical port (docs/protocols.md "Electrical port"): known values, as a motor near
// resonance at 300 V gives them, survive encode -> decode on both buses within one count.
TEST(ElectricalRoundTrip, KnownValuesSurviveModbusAndCanWithinOneCount) {
  Telemetry t = sample();
  t.electrical = {0.183456, 0.179012, 61.234, 58.765, -4.321, 3.219, 8.7654, 8.1234};
  t.stator_temperature_c = 20.004;
  const ElectricalValues& e = t.electrical;
  constexpr double kCurrentCount = 1e-4, kDegreeCount = 0.01, kPowerCount = 0.01, kTemperatureCount = 0.01;

  std::array<std::uint16_t, modbus::input::kCount> r{};
  modbus::fill_input(t, RejectSnapshot{}, r);
  const Telemetry m = modbus::decode_input(r).telemetry;
  EXPECT_NEAR(m.electrical.current_a_a, e.current_a_a, kCurrentCount);
  EXPECT_NEAR(m.electrical.current_b_a, e.current_b_a, kCurrentCount);
  EXPECT_NEAR(m.electrical.phase_a_deg, e.phase_a_deg, kDegreeCount);
  EXPECT_NEAR(m.electrical.phase_b_deg, e.phase_b_deg, kDegreeCount);
  EXPECT_NEAR(m.electrical.motional_phase_a_deg, e.motional_phase_a_deg, kDegreeCount);
  EXPECT_NEAR(m.electrical.motional_phase_b_deg, e.motional_phase_b_deg, kDegreeCount);
  EXPECT_NEAR(m.electrical.power_a_w, e.power_a_w, kPowerCount);
  EXPECT_NEAR(m.electrical.power_b_w, e.power_b_w, kPowerCount);
  EXPECT_NEAR(m.stator_temperature_c, t.stator_temperature_c, kTemperatureCount);

  const can::Ids ids = can::ids_for_node(1);
  can::ElectricalFields a, b;
  ASSERT_EQ(can::decode_electrical(can::encode_electrical_a(t, ids.electrical_a), a), Reason::none);
  ASSERT_EQ(can::decode_electrical(can::encode_electrical_b(t, ids.electrical_b), b), Reason::none);
  EXPECT_NEAR(a.current_a, e.current_a_a, kCurrentCount);
  EXPECT_NEAR(b.current_a, e.current_b_a, kCurrentCount);
  EXPECT_NEAR(a.phase_deg, e.phase_a_deg, kDegreeCount);
  EXPECT_NEAR(b.phase_deg, e.phase_b_deg, kDegreeCount);
  EXPECT_NEAR(a.motional_phase_deg, e.motional_phase_a_deg, kDegreeCount);
  EXPECT_NEAR(b.motional_phase_deg, e.motional_phase_b_deg, kDegreeCount);
  EXPECT_NEAR(a.power_w, e.power_a_w, kPowerCount);
  EXPECT_NEAR(b.power_w, e.power_b_w, kPowerCount);
  can::StatusFields s;
  ASSERT_EQ(can::decode_status(can::encode_status(t, RejectSnapshot{}, 0, ids.status), s), Reason::none);
  EXPECT_NEAR(s.stator_temperature_c, t.stator_temperature_c, kTemperatureCount);
  // Both buses carry the same counts: a controller reads the same numbers whichever it uses.
  EXPECT_DOUBLE_EQ(a.current_a, m.electrical.current_a_a);
  EXPECT_DOUBLE_EQ(b.power_w, m.electrical.power_b_w);
  EXPECT_DOUBLE_EQ(s.stator_temperature_c, m.stator_temperature_c);
}

}  // namespace
}  // namespace swum::protocol
