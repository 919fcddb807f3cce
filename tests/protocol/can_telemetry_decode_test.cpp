// The controller-side decoders invert the emulator's encoders (same DBC layout), so the host
// tool reads exactly what swum-emu sends.
#include "can_telemetry_decode.h"

#include <gtest/gtest.h>

#include "can_codec.h"

namespace swum::protocol::can {
namespace {

Telemetry sample_telemetry() {
  Telemetry t;
  t.state = AmpState::enabled;
  t.fault = FaultCode::none;
  t.enable_line = true;
  t.at_setpoint = false;
  t.output.amplitude_v = 312.5;
  t.output.frequency_hz = 39876.543;
  t.output.phase_deg = -90.25;
  t.output.load_n = -1.234;
  t.speed_m_s = -0.456789;
  t.position_m = 1.234567;
  t.tip_normal_um = 2.345;
  t.tip_tangential_um = 3.456;
  t.applied_commands = 300;  // 44 mod 256
  t.stats.lateness_p50_ns = 4'000;
  t.stats.lateness_p99_ns = 14'000;
  t.stats.lateness_p999_ns = 40'000;
  t.stats.lateness_max_ns = 1'300'000;
  t.stats.overruns = 70'000;  // saturates at 65535 on CAN
  t.electrical = {0.12345, 0.06789, 45.678, -12.345, -2.345, 3.456, 23.456, 7.891};
  t.stator_temperature_c = 27.345;
  return t;
}

TEST(CanTelemetryDecode, InvertsEveryEncoder) {
  const Ids ids = ids_for_node(3);
  const Telemetry t = sample_telemetry();
  StatusFields s;
  ASSERT_EQ(decode_status(encode_status(t, {Reason::phase_out_of_range, 513}, 77, ids.status), s), Reason::none);
  EXPECT_EQ(s.state, 1);
  EXPECT_TRUE(s.enable_line);
  EXPECT_TRUE(s.drive_on);
  EXPECT_FALSE(s.at_setpoint);
  EXPECT_EQ(s.last_reject, static_cast<int>(Reason::phase_out_of_range));
  EXPECT_EQ(s.reject_count, 513 % 256);
  EXPECT_EQ(s.applied_count, 300 % 256);
  EXPECT_EQ(s.status_counter, 77);
  EXPECT_NEAR(s.stator_temperature_c, 27.345, 0.01);  // within one count

  MotionFields m;
  ASSERT_EQ(decode_motion(encode_motion(t, ids.motion), m), Reason::none);
  EXPECT_NEAR(m.speed_mm_s, -456.789, 1e-3);
  EXPECT_NEAR(m.position_mm, 1234.567, 1e-3);

  DriveFields d;
  ASSERT_EQ(decode_drive(encode_drive(t, ids.drive), d), Reason::none);
  EXPECT_NEAR(d.tip_normal_um, 2.345, 1e-3);
  EXPECT_NEAR(d.tip_tangential_um, 3.456, 1e-3);
  EXPECT_NEAR(d.amplitude_v, 312.5, 0.05);
  EXPECT_NEAR(d.phase_deg, -90.25, 0.005);

  LoopStatsFields l;
  ASSERT_EQ(decode_loop_stats(encode_loop_stats(t, ids.loop_stats), l), Reason::none);
  EXPECT_EQ(l.lateness_p99_us, 14.0);
  EXPECT_EQ(l.lateness_max_us, 1300.0);
  EXPECT_EQ(l.overruns, 65535u);

  OutputFields o;
  ASSERT_EQ(decode_output(encode_output(t, ids.output), o), Reason::none);
  EXPECT_NEAR(o.frequency_hz, 39876.543, 1e-3);
  EXPECT_NEAR(o.load_n, -1.234, 1e-3);
  EXPECT_EQ(o.lateness_p50_us, 4.0);

  Telemetry timed = t;
  timed.sim_time_s = 98.7654;
  timed.tick = 987654;
  ClockFields c;
  ASSERT_EQ(decode_clock(encode_clock(timed, ids.clock), c), Reason::none);
  EXPECT_NEAR(c.sim_time_s, 98.765, 1e-9);
  EXPECT_EQ(c.tick, 987654u);

  ElectricalFields a, b;
  ASSERT_EQ(decode_electrical(encode_electrical_a(t, ids.electrical_a), a), Reason::none);
  ASSERT_EQ(decode_electrical(encode_electrical_b(t, ids.electrical_b), b), Reason::none);
  EXPECT_NEAR(a.current_a, 0.12345, 1e-4);  // within one count
  EXPECT_NEAR(a.phase_deg, 45.678, 0.01);
  EXPECT_NEAR(a.motional_phase_deg, -2.345, 0.01);
  EXPECT_NEAR(a.power_w, 23.456, 0.01);
  EXPECT_NEAR(b.current_a, 0.06789, 1e-4);
  EXPECT_NEAR(b.phase_deg, -12.345, 0.01);
  EXPECT_NEAR(b.motional_phase_deg, 3.456, 0.01);
  EXPECT_NEAR(b.power_w, 7.891, 0.01);
}

TEST(CanTelemetryDecode, RefusesShortFrames) {
  CanFrame f = encode_motion(sample_telemetry(), 0x281);
  f.dlc = 4;
  MotionFields m;
  EXPECT_EQ(decode_motion(f, m), Reason::wrong_length);
  f.dlc = 8;
  f.extended = true;
  EXPECT_EQ(decode_motion(f, m), Reason::wrong_length);
  CanFrame e = encode_electrical_a(sample_telemetry(), 0x681);
  e.dlc = 7;
  ElectricalFields ef;
  EXPECT_EQ(decode_electrical(e, ef), Reason::wrong_length);
}

}  // namespace
}  // namespace swum::protocol::can
