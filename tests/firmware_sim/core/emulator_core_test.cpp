#include "core/emulator_core.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "../emu_test_support.h"
#include "analysis/steady_state/steady_state.h"

namespace swum::emu {
namespace {

CoreConfig core_config(double watchdog_s) {
  CoreConfig c;
  c.tick_hz = 10000.0;
  c.amplifier.watchdog_s = watchdog_s;
  return c;
}

void submit(SharedState& shared, Command c) { ASSERT_EQ(shared.submit(c), Reason::none); }

Command run_at(double amplitude_v, double frequency_hz) {
  Command c;
  c.fields = Command::kAction | Command::kAmplitude | Command::kFrequency;
  c.action = Action::enable;
  c.amplitude_v = amplitude_v;
  c.frequency_hz = frequency_hz;
  return c;
}

TEST(EmulatorCore, TickIsAWholeNumberOfModelStepsAt10kHz) {
  SharedState shared;
  EmulatorCore core(test::li2019_model(), core_config(0), shared);
  // 100 us tick / the config's 520.83 ns step (48 steps per 40 kHz period) = 192 steps.
  EXPECT_EQ(core.steps_per_tick(), 192U);
  EXPECT_NEAR(core.steps_per_tick() * test::li2019_model().time_step_s(), 1e-4, 1e-12);
  core.tick();
  EXPECT_NEAR(core.telemetry().sim_time_s, 1e-4, 1e-12);
  EXPECT_EQ(shared.telemetry.load().tick, 1U);
}

TEST(EmulatorCore, SteadySpeedMatchesRunToSteadyState) {
  SharedState shared;
  EmulatorCore core(test::li2019_model(), core_config(0), shared);
  submit(shared, run_at(400, 40000));
  for (int i = 0; i < 800; ++i) core.tick();  // 80 ms
  const SteadyStateResult ref = run_to_steady_state(test::li2019_model(), OperatingPoint{400, 40000, 0, 90});
  ASSERT_TRUE(ref.ok);
  const Telemetry& t = core.telemetry();
  EXPECT_EQ(t.state, AmpState::enabled);
  EXPECT_NEAR(t.speed_m_s * 1e3, ref.speed_mm_s, 0.03 * std::abs(ref.speed_mm_s) + 2.0);
  EXPECT_NEAR(t.tip_normal_um, ref.tip_normal_um, 0.05 * ref.tip_normal_um);
  EXPECT_NEAR(t.tip_tangential_um, ref.tip_tangential_um, 0.05 * ref.tip_tangential_um + 0.02);
  EXPECT_GT(t.position_m, 0.005);  // moved several mm
  EXPECT_EQ(t.applied_commands, 1U);
}

TEST(EmulatorCore, NegativePhaseReversesTheDirection) {
  SharedState shared;
  EmulatorCore core(test::li2019_model(), core_config(0), shared);
  Command c = run_at(400, 40000);
  c.fields |= Command::kPhase;
  c.phase_deg = -90;
  submit(shared, c);
  for (int i = 0; i < 500; ++i) core.tick();
  EXPECT_LT(core.telemetry().speed_m_s, -0.05);
}

TEST(EmulatorCore, WatchdogFaultsAndTheMoverCoastsToRest) {
  SharedState shared;
  EmulatorCore core(test::li2019_model(), core_config(0.02), shared);
  submit(shared, run_at(400, 40000));
  for (int i = 0; i < 150; ++i) {
    if (i % 10 == 0) submit(shared, Command{});  // keep-alive every 1 ms
    core.tick();
  }
  EXPECT_EQ(core.telemetry().state, AmpState::enabled);
  EXPECT_GT(core.telemetry().speed_m_s, 0.05);
  for (int i = 0; i < 201; ++i) core.tick();  // silence > 20 ms
  EXPECT_EQ(core.telemetry().state, AmpState::fault);
  EXPECT_EQ(core.telemetry().fault, FaultCode::command_timeout);
  EXPECT_EQ(core.telemetry().output.amplitude_v, 0.0);
  for (int i = 0; i < 1000; ++i) core.tick();  // 100 ms more
  EXPECT_LT(std::abs(core.telemetry().speed_m_s), 1e-4);
}

TEST(EmulatorCore, NumericalBlowUpRaisesAFaultAndKeepsRunning) {
  SharedState shared;
  EmulatorCore core(test::li2019_model(), core_config(0), shared);
  submit(shared, run_at(400, 40000));
  for (int i = 0; i < 10; ++i) core.tick();
  MotorState s = core.simulator().state();
  s.q1_m = std::numeric_limits<double>::quiet_NaN();
  core.simulator().set_state(s);
  core.tick();
  const Telemetry& t = core.telemetry();
  EXPECT_EQ(t.state, AmpState::fault);
  EXPECT_EQ(t.fault, FaultCode::numerical);
  EXPECT_EQ(t.output.amplitude_v, 0.0);
  EXPECT_TRUE(std::isfinite(t.position_m));
  EXPECT_TRUE(std::isfinite(t.speed_m_s));
  EXPECT_GE(t.divergences, 1U);
  for (int i = 0; i < 10; ++i) core.tick();
  EXPECT_TRUE(std::isfinite(core.telemetry().tip_normal_um));
  // Reset, enable again: it runs.
  Command reset;
  reset.fields = Command::kAction;
  reset.action = Action::reset_fault;
  submit(shared, reset);
  submit(shared, run_at(400, 40000));
  for (int i = 0; i < 300; ++i) core.tick();
  EXPECT_EQ(core.telemetry().state, AmpState::enabled);
  EXPECT_GT(core.telemetry().speed_m_s, 0.05);
}

TEST(EmulatorCore, EnableLineLowTurnsTheDriveOff) {
  SharedState shared;
  EmulatorCore core(test::li2019_model(), core_config(0), shared);
  submit(shared, run_at(400, 40000));
  for (int i = 0; i < 20; ++i) core.tick();
  EXPECT_GT(core.telemetry().output.amplitude_v, 0.0);
  shared.enable_line = false;
  core.tick();
  EXPECT_EQ(core.telemetry().output.amplitude_v, 0.0);
  EXPECT_EQ(core.telemetry().state, AmpState::disabled);
  submit(shared, run_at(400, 40000));
  core.tick();
  EXPECT_EQ(core.telemetry().state, AmpState::disabled);
  EXPECT_EQ(static_cast<Reason>(shared.rejects.last_reason.load()), Reason::enable_line_low);
}

TEST(EmulatorCore, CommandsApplyInOrderAtTheNextTick) {
  SharedState shared;
  EmulatorCore core(test::li2019_model(), core_config(0), shared);
  for (int i = 1; i <= 100; ++i) {
    Command c;
    c.fields = Command::kAmplitude;
    c.amplitude_v = i;
    submit(shared, c);
  }
  EXPECT_EQ(core.telemetry().applied_commands, 0U);
  core.tick();
  EXPECT_EQ(core.telemetry().applied_commands, 100U);
  EXPECT_DOUBLE_EQ(core.telemetry().setpoints.amplitude_v, 100.0);
}

TEST(EmulatorCore, FullQueueRefusesInsteadOfDropping) {
  SharedState shared;
  EmulatorCore core(test::li2019_model(), core_config(0), shared);
  std::size_t accepted = 0;
  for (std::size_t i = 0; i < kCommandQueueCapacity + 10; ++i)
    if (shared.submit(Command{}) == Reason::none) ++accepted;
  EXPECT_EQ(accepted, kCommandQueueCapacity);
  EXPECT_EQ(shared.queue_full.load(), 10U);
  core.tick();
  EXPECT_EQ(core.telemetry().applied_commands, accepted);
}

}  // namespace
}  // namespace swum::emu
