// LockstepClock / LockstepLoop: exactly the ticks asked for, commands queued before a step act
// from its first tick, a stopped emulator answers every waiting step, no timing in the telemetry.
#include "core/lockstep_clock.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "../emu_test_support.h"

namespace swum::emu {
namespace {

struct Rig {
  SharedState shared;
  LockstepClock clock;
  EmulatorCore core;
  std::atomic<bool> stop{false};
  explicit Rig(CoreConfig config = {}) : core(test::li2019_model(), with_clock(config), shared) {
    shared.lockstep = &clock;
  }
  static CoreConfig with_clock(CoreConfig c) {
    c.external_clock = true;
    return c;
  }
};

Command enable_at(double amplitude_v) {
  Command c;
  c.fields = Command::kAction | Command::kAmplitude | Command::kFrequency;
  c.action = Action::enable;
  c.amplitude_v = amplitude_v;
  c.frequency_hz = 40000.0;
  c.source = CommandSource::modbus;
  return c;
}

TEST(LockstepLoop, RunsExactlyTheTicksAskedForAndNoMore) {
  Rig rig;
  LockstepLoop loop(rig.core, rig.clock, {});
  std::thread thread([&] { loop.run(rig.stop); });
  EXPECT_TRUE(rig.clock.advance(7));
  EXPECT_EQ(rig.core.ticks(), 7U);
  EXPECT_TRUE(rig.clock.advance(1));
  EXPECT_TRUE(rig.clock.advance(100));
  EXPECT_EQ(rig.core.ticks(), 108U);
  EXPECT_EQ(rig.shared.telemetry.load().tick, 108U);
  EXPECT_TRUE(rig.shared.telemetry.load().external_clock);
  rig.stop = true;
  thread.join();
  EXPECT_EQ(rig.core.ticks(), 108U);  // nothing ran without a request
}

TEST(LockstepLoop, CommandQueuedBeforeAStepActsFromItsFirstTick) {
  Rig rig;
  LockstepLoop loop(rig.core, rig.clock, {});
  std::thread thread([&] { loop.run(rig.stop); });
  ASSERT_EQ(rig.shared.submit(enable_at(300.0)), Reason::none);
  ASSERT_TRUE(rig.clock.advance(1));
  const Telemetry t = rig.shared.telemetry.load();
  EXPECT_EQ(t.state, AmpState::enabled);
  EXPECT_EQ(t.applied_commands, 1U);
  EXPECT_GT(t.output.amplitude_v, 0.0);  // driving during that very tick (slew-limited)
  rig.stop = true;
  thread.join();
}

TEST(LockstepLoop, WatchdogCountsEmulatedTicksNotWallTime) {
  CoreConfig config;
  config.amplifier.watchdog_s = 0.1;  // 1000 ticks at 10 kHz
  Rig rig(config);
  LockstepLoop loop(rig.core, rig.clock, {});
  std::thread thread([&] { loop.run(rig.stop); });
  ASSERT_EQ(rig.shared.submit(enable_at(100.0)), Reason::none);
  ASSERT_TRUE(rig.clock.advance(1001));  // command at tick 0: faults at the first tick after 0 + 1000
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // wall time passes: no effect
  EXPECT_EQ(rig.shared.telemetry.load().state, AmpState::enabled);
  ASSERT_TRUE(rig.clock.advance(1));
  EXPECT_EQ(rig.shared.telemetry.load().fault, FaultCode::command_timeout);
  rig.stop = true;
  thread.join();
}

TEST(LockstepLoop, DurationEndsTheRunAndEveryWaitingStepIsAnswered) {
  Rig rig;
  LockstepLoop loop(rig.core, rig.clock, LockstepConfig{50});
  std::thread thread([&] { loop.run(rig.stop); });
  EXPECT_TRUE(rig.clock.advance(40));
  EXPECT_FALSE(rig.clock.advance(20));  // only 10 of them run
  thread.join();
  EXPECT_EQ(rig.core.ticks(), 50U);
  EXPECT_FALSE(rig.clock.advance(1));  // closed
}

TEST(LockstepLoop, ConcurrentStepsAreServedInFullAndInOrder) {
  Rig rig;
  LockstepLoop loop(rig.core, rig.clock, {});
  std::thread thread([&] { loop.run(rig.stop); });
  std::vector<std::thread> clients;
  std::atomic<int> answered{0};
  for (int i = 0; i < 4; ++i)
    clients.emplace_back([&] {
      for (int k = 0; k < 25; ++k) answered += rig.clock.advance(3) ? 1 : 0;
    });
  for (auto& c : clients) c.join();
  EXPECT_EQ(answered.load(), 100);
  EXPECT_EQ(rig.core.ticks(), 300U);
  rig.stop = true;
  thread.join();
}

TEST(LockstepLoop, TimingFieldsStayZero) {
  Rig rig;
  LockstepLoop loop(rig.core, rig.clock, {});
  std::thread thread([&] { loop.run(rig.stop); });
  ASSERT_TRUE(rig.clock.advance(5000));
  const Telemetry t = rig.shared.telemetry.load();
  EXPECT_EQ(t.stats.overruns, 0U);
  EXPECT_EQ(t.stats.lateness_max_ns, 0U);
  EXPECT_EQ(t.stats.compute_max_ns, 0U);
  rig.stop = true;
  thread.join();
}

}  // namespace
}  // namespace swum::emu
