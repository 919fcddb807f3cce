#include "core/amplifier.h"

#include <gtest/gtest.h>

#include <cmath>

namespace swum::emu {
namespace {

AmplifierConfig config() {
  AmplifierConfig c;
  c.tick_s = 1e-4;
  c.watchdog_s = 0.01;              // 100 ticks
  c.amplitude_slew_v_per_s = 1e5;   // 10 V per tick
  c.frequency_slew_hz_per_s = 1e6;  // 100 Hz per tick
  return c;
}
Command action(Action a) {
  Command c;
  c.fields = Command::kAction;
  c.action = a;
  return c;
}
Command amplitude(double amplitude_v) {
  Command c;
  c.fields = Command::kAmplitude;
  c.amplitude_v = amplitude_v;
  return c;
}

TEST(Amplifier, StartsDisabledWithNoDrive) {
  Amplifier amp(config());
  EXPECT_EQ(amp.state(), AmpState::disabled);
  EXPECT_EQ(amp.tick(0, true).amplitude_v, 0.0);
}

TEST(Amplifier, EnableRampsAmplitudeAtTheSlewLimit) {
  Amplifier amp(config());
  EXPECT_EQ(amp.apply(amplitude(400), 0), Reason::none);
  EXPECT_EQ(amp.tick(0, true).amplitude_v, 0.0);  // still disabled
  EXPECT_EQ(amp.apply(action(Action::enable), 1), Reason::none);
  EXPECT_EQ(amp.state(), AmpState::enabled);
  EXPECT_NEAR(amp.tick(1, true).amplitude_v, 10.0, 1e-9);
  EXPECT_NEAR(amp.tick(2, true).amplitude_v, 20.0, 1e-9);
  for (std::uint64_t t = 3; t < 60; ++t) amp.tick(t, true);
  EXPECT_DOUBLE_EQ(amp.output().amplitude_v, 400.0);
  EXPECT_TRUE(amp.at_setpoint());
}

TEST(Amplifier, FrequencySlewsWhileEnabledAndJumpsWhileDisabled) {
  Amplifier amp(config());
  Command f;
  f.fields = Command::kFrequency;
  f.frequency_hz = 40500.0;
  amp.apply(f, 0);
  EXPECT_DOUBLE_EQ(amp.tick(0, true).frequency_hz, 40500.0);
  amp.apply(action(Action::enable), 0);
  f.frequency_hz = 40000.0;
  amp.apply(f, 0);
  EXPECT_NEAR(amp.tick(1, true).frequency_hz, 40400.0, 1e-6);
}

TEST(Amplifier, DisableCutsTheDriveAtOnce) {
  Amplifier amp(config());
  amp.apply(amplitude(100), 0);
  amp.apply(action(Action::enable), 0);
  for (std::uint64_t t = 0; t < 20; ++t) amp.tick(t, true);
  EXPECT_GT(amp.output().amplitude_v, 0.0);
  amp.apply(action(Action::disable), 20);
  EXPECT_EQ(amp.tick(20, true).amplitude_v, 0.0);
  EXPECT_EQ(amp.state(), AmpState::disabled);
}

TEST(Amplifier, WatchdogFaultsAfterTheTimeoutAndOnlyResetClearsIt) {
  Amplifier amp(config());
  amp.apply(amplitude(100), 0);
  amp.apply(action(Action::enable), 0);
  for (std::uint64_t t = 0; t <= 100; ++t) {
    amp.tick(t, true);
    ASSERT_EQ(amp.state(), AmpState::enabled) << t;
  }
  amp.tick(101, true);
  EXPECT_EQ(amp.state(), AmpState::fault);
  EXPECT_EQ(amp.fault(), FaultCode::command_timeout);
  EXPECT_EQ(amp.output().amplitude_v, 0.0);
  // Enable is refused in fault; a reset brings it to disabled.
  EXPECT_EQ(amp.apply(action(Action::enable), 102), Reason::fault_active);
  EXPECT_EQ(amp.apply(action(Action::disable), 102), Reason::none);
  EXPECT_EQ(amp.state(), AmpState::fault);
  EXPECT_EQ(amp.apply(action(Action::reset_fault), 103), Reason::none);
  EXPECT_EQ(amp.state(), AmpState::disabled);
  EXPECT_EQ(amp.fault(), FaultCode::none);
}

TEST(Amplifier, KeepAliveFeedsTheWatchdog) {
  Amplifier amp(config());
  amp.apply(action(Action::enable), 0);
  for (std::uint64_t t = 0; t < 1000; ++t) {
    if (t % 50 == 0) amp.apply(Command{}, t);
    amp.tick(t, true);
  }
  EXPECT_EQ(amp.state(), AmpState::enabled);
}

TEST(Amplifier, WatchdogIgnoredWhileDisabled) {
  Amplifier amp(config());
  for (std::uint64_t t = 0; t < 1000; ++t) amp.tick(t, true);
  EXPECT_EQ(amp.state(), AmpState::disabled);
}

TEST(Amplifier, OutOfRangeIsRejectedAndChangesNothing) {
  Amplifier amp(config());
  const AmplifierSetpoints before = amp.setpoints();
  Command c;
  c.fields = Command::kFrequency | Command::kAmplitude;
  c.frequency_hz = 40000.0;
  c.amplitude_v = 700.0;
  EXPECT_EQ(amp.apply(c, 0), Reason::amplitude_out_of_range);
  EXPECT_EQ(amp.setpoints().amplitude_v, before.amplitude_v);
  c.amplitude_v = 100;
  c.frequency_hz = 60000.0;
  EXPECT_EQ(amp.apply(c, 0), Reason::frequency_out_of_range);
  c.frequency_hz = std::nan("");
  EXPECT_EQ(amp.apply(c, 0), Reason::frequency_out_of_range);
  Command p;
  p.fields = Command::kPhase;
  p.phase_deg = 181;
  EXPECT_EQ(amp.apply(p, 0), Reason::phase_out_of_range);
  Command l;
  l.fields = Command::kLoad;
  l.load_n = -31;
  EXPECT_EQ(amp.apply(l, 0), Reason::load_out_of_range);
  Command a;
  a.fields = Command::kAction;
  a.action = static_cast<Action>(9);
  EXPECT_EQ(amp.apply(a, 0), Reason::unknown_command);
  EXPECT_EQ(amp.state(), AmpState::disabled);
  EXPECT_EQ(amp.rejected_commands(), 6U);
  EXPECT_EQ(amp.applied_commands(), 0U);
}

TEST(Amplifier, EnableLineLowForcesDisableAndRefusesEnable) {
  Amplifier amp(config());
  amp.apply(amplitude(100), 0);
  amp.apply(action(Action::enable), 0);
  amp.tick(0, true);
  EXPECT_GT(amp.output().amplitude_v, 0.0);
  EXPECT_EQ(amp.tick(1, false).amplitude_v, 0.0);
  EXPECT_EQ(amp.state(), AmpState::disabled);
  EXPECT_EQ(amp.apply(action(Action::enable), 2), Reason::enable_line_low);
  amp.tick(3, true);
  EXPECT_EQ(amp.apply(action(Action::enable), 4), Reason::none);
}

TEST(Amplifier, RaisedFaultLatches) {
  Amplifier amp(config());
  amp.apply(action(Action::enable), 0);
  amp.raise_fault(FaultCode::numerical);
  EXPECT_EQ(amp.tick(1, true).amplitude_v, 0.0);
  EXPECT_EQ(amp.state(), AmpState::fault);
  EXPECT_EQ(amp.fault(), FaultCode::numerical);
}

TEST(Amplifier, ReasonNamesAreDistinct) {
  for (int i = 0; i <= 16; ++i)
    for (int j = i + 1; j <= 16; ++j)
      EXPECT_STRNE(to_string(static_cast<Reason>(i)), to_string(static_cast<Reason>(j)));
}

}  // namespace
}  // namespace swum::emu
