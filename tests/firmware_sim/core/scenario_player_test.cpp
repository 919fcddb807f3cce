// ScenarioPlayer: the conditions holding during tick k at 10 kHz (tick boundary k / 10 kHz):
// event times rounded to ticks, load profiles, fault durations and clears, phase gains, the
// per-tick counters, the `started` list and the seeded noise.
#include "core/scenario_player.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "../emu_test_support.h"

namespace swum::emu {
namespace {

constexpr double kTickHz = 10000.0;

using test::scenario_of;

// Asks the player for every tick in order, as the core does.
class Timeline {
 public:
  explicit Timeline(Scenario scenario) : player_(std::move(scenario), kTickHz) {}
  // The conditions of `tick`: the last one asked again, or a later one.
  const ScenarioConditions& at(std::uint64_t tick) {
    if (last_ != nullptr && tick + 1 == next_) return *last_;
    EXPECT_GE(tick, next_) << "ticks must be asked in increasing order";
    for (; next_ <= tick; ++next_) last_ = &player_.at_tick(next_);
    return *last_;
  }
  ScenarioPlayer& player() { return player_; }

 private:
  ScenarioPlayer player_;
  std::uint64_t next_ = 0;
  const ScenarioConditions* last_ = nullptr;
};

TEST(ScenarioPlayer, EventTimesRoundToTheNearestTick) {
  // 0.00014 s = 1.4 ticks -> tick 1; 0.00026 s = 2.6 ticks -> tick 3.
  Timeline t(scenario_of({"speed_frozen@0.00014", "encoder_stuck@0.00026"}));
  EXPECT_FALSE(t.at(0).speed_frozen);
  EXPECT_TRUE(t.at(1).speed_frozen);
  EXPECT_FALSE(t.at(2).encoder_stuck);
  EXPECT_TRUE(t.at(3).encoder_stuck);
}

TEST(ScenarioPlayer, NoLoadBeforeTheFirstLoadEventThenTheStep) {
  Timeline t(scenario_of({"load_step@0.01:load_n=2", "load_step@0.02:load_n=-1.5"}));
  EXPECT_FALSE(t.at(99).load_n.has_value());  // the drive's own load until then
  EXPECT_EQ(t.at(100).load_n, 2.0);
  EXPECT_EQ(t.at(199).load_n, 2.0);
  EXPECT_EQ(t.at(200).load_n, -1.5);
  EXPECT_EQ(t.at(5000).load_n, -1.5);
}

TEST(ScenarioPlayer, RampGoesLinearlyFromTheLoadInForceAndStaysAtItsEnd) {
  // From 1 N at tick 100 to 3 N over 0.01 s = 100 ticks.
  Timeline t(scenario_of({"load_step@0:load_n=1", "load_ramp@0.01:to_n=3,duration_s=0.01"}));
  EXPECT_EQ(t.at(99).load_n, 1.0);
  EXPECT_NEAR(*t.at(100).load_n, 1.0, 1e-12);
  EXPECT_NEAR(*t.at(125).load_n, 1.5, 1e-12);
  EXPECT_NEAR(*t.at(150).load_n, 2.0, 1e-12);  // the middle
  EXPECT_NEAR(*t.at(175).load_n, 2.5, 1e-12);
  EXPECT_EQ(t.at(200).load_n, 3.0);
  EXPECT_EQ(t.at(10000).load_n, 3.0);
}

TEST(ScenarioPlayer, RampWithoutAnEarlierLoadStartsFromZero) {
  Timeline t(scenario_of({"load_ramp@0:to_n=-4,duration_s=0.001"}));
  EXPECT_NEAR(*t.at(0).load_n, 0.0, 1e-12);
  EXPECT_NEAR(*t.at(5).load_n, -2.0, 1e-12);
  EXPECT_EQ(t.at(10).load_n, -4.0);
}

TEST(ScenarioPlayer, RampStartsFromTheLoadInForceAtItsOwnStartTick) {
  // docs/scenarios.md: "from its value at at_s". A sine of 10 N amplitude at 25 Hz is at its
  // crest at 0.01 s (tick 100), where the ramp to 0 starts: the ramp's first value is 10 N, not
  // the sine's value one tick earlier (9.998 N).
  Timeline t(
      scenario_of({"load_sine@0:offset_n=0,amplitude_n=10,frequency_hz=25", "load_ramp@0.01:to_n=0,duration_s=0.01"}));
  EXPECT_NEAR(*t.at(100).load_n, 10.0, 1e-9);
  EXPECT_NEAR(*t.at(150).load_n, 5.0, 1e-9);
  // A step and a ramp at the same time: the step (first in file order) is the ramp's start.
  Timeline same(
      scenario_of({"load_step@0:load_n=1", "load_step@0.001:load_n=6", "load_ramp@0.001:to_n=0,duration_s=0.001"}));
  EXPECT_NEAR(*same.at(10).load_n, 6.0, 1e-12);
  EXPECT_NEAR(*same.at(15).load_n, 3.0, 1e-12);
}

TEST(ScenarioPlayer, SineHasItsCrestAtAQuarterPeriodAndEndsAtItsOffset) {
  // 1 + 2 sin(2 pi 25 Hz t) for 0.1 s from 0.01 s: crest 3 N at 0.01 + 0.01 s (tick 200).
  Timeline t(scenario_of({"load_sine@0.01:offset_n=1,amplitude_n=2,frequency_hz=25,duration_s=0.1"}));
  EXPECT_NEAR(*t.at(100).load_n, 1.0, 1e-12);
  EXPECT_NEAR(*t.at(200).load_n, 3.0, 1e-12);
  EXPECT_NEAR(*t.at(300).load_n, 1.0, 1e-12);   // half period
  EXPECT_NEAR(*t.at(400).load_n, -1.0, 1e-12);  // trough
  EXPECT_NEAR(*t.at(1099).load_n, 1.0 + 2.0 * std::sin(2.0 * std::numbers::pi * 25.0 * 0.0999), 1e-9);
  EXPECT_EQ(t.at(1100).load_n, 1.0);  // ended: the offset stays
  EXPECT_EQ(t.at(5000).load_n, 1.0);
}

TEST(ScenarioPlayer, SineOfZeroDurationLastsUntilTheNextLoadEvent) {
  Timeline t(scenario_of({"load_sine@0:offset_n=0,amplitude_n=5,frequency_hz=10", "load_step@2:load_n=-1"}));
  // 1.025 s = 10.25 periods: a crest, long after any duration would have ended.
  EXPECT_NEAR(*t.at(10250).load_n, 5.0, 1e-9);
  EXPECT_NEAR(*t.at(19750).load_n, -5.0, 1e-9);  // 1.975 s = 19.75 periods: a trough
  EXPECT_EQ(t.at(20000).load_n, -1.0);
}

TEST(ScenarioPlayer, DurationEndsTheFaultAtItsStartTickPlusTheRoundedDuration) {
  // Start tick 10; 0.00234 s = 23.4 ticks -> ends at tick 33; 0.00236 s = 23.6 -> tick 34.
  Timeline t(scenario_of(
      {"voltage_sag@0.001:factor=0.5,duration_s=0.00234", "speed_bias@0.001:bias_mm_s=3,duration_s=0.00236"}));
  EXPECT_EQ(t.at(9).phase_a_gain, 1.0);
  EXPECT_EQ(t.at(10).phase_a_gain, 0.5);
  EXPECT_EQ(t.at(10).speed_bias_mm_s, 3.0);
  EXPECT_EQ(t.at(32).phase_b_gain, 0.5);
  EXPECT_EQ(t.at(33).phase_b_gain, 1.0);
  EXPECT_EQ(t.at(33).speed_bias_mm_s, 3.0);
  EXPECT_EQ(t.at(34).speed_bias_mm_s, 0.0);
}

TEST(ScenarioPlayer, ClearEndsEveryActiveFaultOfItsTypeOnly) {
  Timeline t(scenario_of({"phase_open@0:phase=A", "phase_open@0:phase=B,duration_s=1", "voltage_sag@0:factor=0.8",
                          "clear@0.01:fault=phase_open"}));
  EXPECT_EQ(t.at(99).phase_a_gain, 0.0);
  EXPECT_EQ(t.at(99).phase_b_gain, 0.0);
  const ScenarioConditions& c = t.at(100);
  EXPECT_EQ(c.phase_a_gain, 0.8);  // both opens ended; the sag holds
  EXPECT_EQ(c.phase_b_gain, 0.8);
}

TEST(ScenarioPlayer, PhaseOpenTimesVoltageSagGivesThePhaseGains) {
  Timeline t(scenario_of({"voltage_sag@0:factor=0.7", "phase_open@0.001:phase=A,duration_s=0.001",
                          "phase_open@0.003:phase=B,duration_s=0.001"}));
  EXPECT_EQ(t.at(0).phase_a_gain, 0.7);
  EXPECT_EQ(t.at(0).phase_b_gain, 0.7);
  EXPECT_EQ(t.at(10).phase_a_gain, 0.0);
  EXPECT_EQ(t.at(10).phase_b_gain, 0.7);
  EXPECT_EQ(t.at(20).phase_a_gain, 0.7);
  EXPECT_EQ(t.at(30).phase_a_gain, 0.7);
  EXPECT_EQ(t.at(30).phase_b_gain, 0.0);
}

TEST(ScenarioPlayer, PhaseShortAndOverTemperatureHoldUntilCleared) {
  Timeline t(scenario_of({"phase_short@0.001:phase=B", "over_temperature@0.002", "clear@50:fault=phase_short",
                          "clear@60:fault=over_temperature"}));
  EXPECT_FALSE(t.at(9).over_current);
  EXPECT_TRUE(t.at(10).over_current);
  EXPECT_FALSE(t.at(10).over_temperature);
  EXPECT_TRUE(t.at(20).over_temperature);
  const ScenarioConditions& late = t.at(499999);  // 50 s later: still holding
  EXPECT_TRUE(late.over_current);
  EXPECT_TRUE(late.over_temperature);
  EXPECT_FALSE(t.at(500000).over_current);
  EXPECT_TRUE(t.at(500000).over_temperature);
  EXPECT_FALSE(t.at(600000).over_temperature);
}

TEST(ScenarioPlayer, EachJamHasANewGenerationAndItsPosition) {
  Timeline t(scenario_of({"jam@0.001:duration_s=0.001", "jam@0.003:position_um=120", "clear@0.004:fault=jam",
                          "jam@0.005:position_um=120"}));
  EXPECT_FALSE(t.at(9).jammed);
  EXPECT_EQ(t.at(9).jam_generation, 0U);
  const ScenarioConditions& first = t.at(10);
  EXPECT_TRUE(first.jammed);
  EXPECT_EQ(first.jam_generation, 1U);
  EXPECT_FALSE(first.jam_position_um.has_value());  // where the mover is
  EXPECT_FALSE(t.at(20).jammed);
  const ScenarioConditions& second = t.at(30);
  EXPECT_TRUE(second.jammed);
  EXPECT_EQ(second.jam_generation, 2U);
  EXPECT_EQ(second.jam_position_um, 120.0);
  EXPECT_FALSE(t.at(40).jammed);
  const ScenarioConditions& third = t.at(50);  // the same place again: still a new jam
  EXPECT_EQ(third.jam_generation, 3U);
  EXPECT_EQ(t.at(60).jam_generation, 3U);
}

TEST(ScenarioPlayer, ModbusDropsCountOnlyAtTheirStartTick) {
  Timeline t(scenario_of({"modbus_drop@0.001:count=3", "modbus_drop@0.001:count=2", "modbus_drop@0.002"}));
  EXPECT_EQ(t.at(9).modbus_drops_started, 0U);
  EXPECT_EQ(t.at(10).modbus_drops_started, 5U);
  EXPECT_EQ(t.at(11).modbus_drops_started, 0U);
  EXPECT_EQ(t.at(20).modbus_drops_started, 1U);
  EXPECT_EQ(t.at(21).modbus_drops_started, 0U);
}

TEST(ScenarioPlayer, StartedListsExactlyTheEventsStartingAtThatTick) {
  Timeline t(scenario_of({"load_step@0:load_n=1", "modbus_delay@0.001:delay_ms=5", "can_bus_off@0.001:duration_s=1",
                          "clear@0.002:fault=modbus_delay"}));
  const std::vector<ScenarioEvent>& events = t.player().scenario().events;
  EXPECT_EQ(t.at(0).started, (std::vector<const ScenarioEvent*>{&events[0]}));
  EXPECT_TRUE(t.at(1).started.empty());
  EXPECT_TRUE(t.at(9).started.empty());
  const ScenarioConditions& c = t.at(10);
  EXPECT_EQ(c.started, (std::vector<const ScenarioEvent*>{&events[1], &events[2]}));
  EXPECT_EQ(c.modbus_delay_ms, 5.0);
  EXPECT_TRUE(c.can_bus_off);
  EXPECT_TRUE(t.at(11).started.empty());
  const ScenarioConditions& cleared = t.at(20);
  EXPECT_EQ(cleared.started, (std::vector<const ScenarioEvent*>{&events[3]}));
  EXPECT_EQ(cleared.modbus_delay_ms, 0.0);
  EXPECT_TRUE(cleared.can_bus_off);
}

TEST(ScenarioPlayer, CommunicationAndSensorFaultsWhileTheyLast) {
  Timeline t(scenario_of({"telemetry_silence@0:duration_s=0.001", "encoder_noise@0:sigma_um=2.5,duration_s=0.002",
                          "speed_noise@0:sigma_mm_s=4,duration_s=0.003", "speed_frozen@0:duration_s=0.004"}));
  const ScenarioConditions& c = t.at(0);
  EXPECT_TRUE(c.telemetry_silent);
  EXPECT_EQ(c.encoder_sigma_um, 2.5);
  EXPECT_EQ(c.speed_sigma_mm_s, 4.0);
  EXPECT_TRUE(c.speed_frozen);
  EXPECT_FALSE(t.at(10).telemetry_silent);
  EXPECT_EQ(t.at(20).encoder_sigma_um, 0.0);
  EXPECT_EQ(t.at(30).speed_sigma_mm_s, 0.0);
  EXPECT_FALSE(t.at(40).speed_frozen);
}

std::vector<double> draws(std::uint64_t seed, int n) {
  ScenarioPlayer p(scenario_of({}, seed), kTickHz);
  std::vector<double> v;
  v.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) v.push_back(p.normal());
  return v;
}

TEST(ScenarioPlayer, NormalDrawsAreSeededAndStandard) {
  EXPECT_EQ(draws(7, 101), draws(7, 101));  // bit-identical, odd count (the spare draw too)
  EXPECT_NE(draws(7, 100), draws(8, 100));
  const std::vector<double> v = draws(7, 20000);
  double sum = 0.0, sum_sq = 0.0;
  for (double x : v) sum += x;
  const double mean = sum / static_cast<double>(v.size());
  for (double x : v) sum_sq += (x - mean) * (x - mean);
  const double sd = std::sqrt(sum_sq / static_cast<double>(v.size() - 1));
  // Standard errors over 20000 draws: mean 0.007, sd 0.005; tolerances ~4 of them.
  EXPECT_NEAR(mean, 0.0, 0.03);
  EXPECT_NEAR(sd, 1.0, 0.02);
  int beyond_3_sd = 0;
  for (double x : v) beyond_3_sd += std::abs(x) > 3.0 ? 1 : 0;
  EXPECT_LT(beyond_3_sd, 100);  // expected 54 (0.27 %)
  EXPECT_GT(beyond_3_sd, 20);
}

// --- Run-time faults (the HTTP API): queue_runtime, generation, active_faults --------------------

RuntimeEvent runtime(EventType type) {
  RuntimeEvent e;
  e.type = type;
  return e;
}
RuntimeEvent runtime_phase_open(Phase phase, double duration_s = 0.0) {
  RuntimeEvent e = runtime(EventType::phase_open);
  e.parameters.phase = phase;
  e.parameters.duration_s = duration_s;
  return e;
}
RuntimeEvent runtime_clear(EventType fault) {
  RuntimeEvent e = runtime(EventType::clear);
  e.parameters.fault = fault;
  return e;
}
ActiveFaults active_faults_of(const ScenarioPlayer& player) {
  ActiveFaults out;
  player.active_faults(out);
  return out;
}

TEST(ScenarioPlayerRuntime, QueuedFaultStartsAtTheNextTick) {
  Timeline t(scenario_of({}));
  EXPECT_FALSE(t.at(9).over_temperature);
  EXPECT_TRUE(t.player().queue_runtime(runtime(EventType::over_temperature)));
  EXPECT_FALSE(t.at(9).over_temperature);  // tick 9's conditions stay what they were
  EXPECT_TRUE(t.at(10).over_temperature);
  EXPECT_TRUE(t.at(100000).over_temperature);  // no duration: until cleared
}

TEST(ScenarioPlayerRuntime, QueuedFaultLastsItsDurationInTicks) {
  Timeline t(scenario_of({}));
  t.at(9);
  ASSERT_TRUE(t.player().queue_runtime(runtime_phase_open(Phase::B, 0.0025)));  // 25 ticks
  EXPECT_EQ(t.at(10).phase_b_gain, 0.0);
  EXPECT_EQ(t.at(10).phase_a_gain, 1.0);
  EXPECT_EQ(t.at(34).phase_b_gain, 0.0);
  EXPECT_EQ(t.at(35).phase_b_gain, 1.0);
}

TEST(ScenarioPlayerRuntime, ClearByTypeEndsThatTypeOnly) {
  Timeline t(scenario_of({}));
  t.at(0);
  RuntimeEvent sag = runtime(EventType::voltage_sag);
  sag.parameters.factor = 0.5;
  ASSERT_TRUE(t.player().queue_runtime(runtime_phase_open(Phase::A)));
  ASSERT_TRUE(t.player().queue_runtime(sag));
  EXPECT_EQ(t.at(1).phase_a_gain, 0.0);
  EXPECT_EQ(t.at(1).phase_b_gain, 0.5);
  ASSERT_TRUE(t.player().queue_runtime(runtime_clear(EventType::phase_open)));
  const ScenarioConditions& c = t.at(2);
  EXPECT_EQ(c.phase_a_gain, 0.5);  // the open ended; the sag holds
  EXPECT_EQ(c.phase_b_gain, 0.5);
  EXPECT_EQ(active_faults_of(t.player()).count, 1U);
}

TEST(ScenarioPlayerRuntime, ClearAllEndsEveryFaultTheFilesToo) {
  Timeline t(scenario_of({"voltage_sag@0:factor=0.5", "speed_frozen@0", "load_step@0:load_n=2"}));
  t.at(0);
  ASSERT_TRUE(t.player().queue_runtime(runtime(EventType::over_temperature)));
  const ScenarioConditions& before = t.at(1);
  EXPECT_EQ(before.phase_a_gain, 0.5);
  EXPECT_TRUE(before.speed_frozen);
  EXPECT_TRUE(before.over_temperature);
  ASSERT_TRUE(t.player().queue_runtime(runtime_clear(EventType::clear)));
  const ScenarioConditions& after = t.at(2);
  EXPECT_EQ(after.phase_a_gain, 1.0);
  EXPECT_FALSE(after.speed_frozen);
  EXPECT_FALSE(after.over_temperature);
  EXPECT_EQ(after.load_n, 2.0);  // a load is not a fault: it stays
  EXPECT_EQ(active_faults_of(t.player()).count, 0U);
}

TEST(ScenarioPlayerRuntime, GenerationChangesWhenAFaultStartsEndsOrIsCleared) {
  Timeline t(scenario_of({}));
  t.at(0);
  const std::uint64_t g0 = t.player().generation();
  ASSERT_TRUE(t.player().queue_runtime(runtime_phase_open(Phase::A, 0.001)));  // ticks 1..10
  t.at(1);
  const std::uint64_t started = t.player().generation();
  EXPECT_NE(started, g0);
  t.at(10);
  EXPECT_EQ(t.player().generation(), started);  // nothing changed in between
  t.at(11);
  const std::uint64_t ended = t.player().generation();
  EXPECT_NE(ended, started);
  ASSERT_TRUE(t.player().queue_runtime(runtime(EventType::encoder_stuck)));
  t.at(12);
  const std::uint64_t second = t.player().generation();
  EXPECT_NE(second, ended);
  ASSERT_TRUE(t.player().queue_runtime(runtime_clear(EventType::encoder_stuck)));
  t.at(13);
  EXPECT_NE(t.player().generation(), second);
  EXPECT_EQ(active_faults_of(t.player()).generation, t.player().generation());
}

TEST(ScenarioPlayerRuntime, FileFaultsChangeTheGenerationToo) {
  Timeline t(scenario_of({"speed_frozen@0.001:duration_s=0.001"}));
  EXPECT_FALSE(t.at(9).speed_frozen);
  const std::uint64_t before = t.player().generation();
  EXPECT_TRUE(t.at(10).speed_frozen);
  const std::uint64_t started = t.player().generation();
  EXPECT_NE(started, before);
  EXPECT_FALSE(t.at(20).speed_frozen);
  EXPECT_NE(t.player().generation(), started);
}

TEST(ScenarioPlayerRuntime, ActiveFaultsListTypeTicksAndParametersOfFileAndRuntimeFaults) {
  Timeline t(scenario_of({"voltage_sag@0.001:factor=0.7,duration_s=0.002"}));
  t.at(14);
  ASSERT_TRUE(t.player().queue_runtime(runtime_phase_open(Phase::B, 0.1)));
  t.at(15);
  const ActiveFaults f = active_faults_of(t.player());
  ASSERT_EQ(f.count, 2U);
  EXPECT_EQ(f.items[0].type, EventType::voltage_sag);  // in the order they started
  EXPECT_EQ(f.items[0].since_tick, 10U);
  EXPECT_EQ(f.items[0].until_tick, 30U);
  EXPECT_EQ(f.items[0].parameters.factor, 0.7);
  EXPECT_EQ(f.items[1].type, EventType::phase_open);
  EXPECT_EQ(f.items[1].since_tick, 15U);
  EXPECT_EQ(f.items[1].until_tick, 1015U);
  EXPECT_EQ(f.items[1].parameters.phase, Phase::B);
  EXPECT_EQ(f.items[1].parameters.duration_s, 0.1);
  EXPECT_EQ(f.refused, 0U);
  t.at(30);  // the sag ended
  const ActiveFaults later = active_faults_of(t.player());
  ASSERT_EQ(later.count, 1U);
  EXPECT_EQ(later.items[0].type, EventType::phase_open);
}

TEST(ScenarioPlayerRuntime, FaultWithoutDurationHoldsUntilClearedInActiveFaults) {
  Timeline t(scenario_of({}));
  t.at(0);
  ASSERT_TRUE(t.player().queue_runtime(runtime(EventType::jam)));
  t.at(1);
  const ActiveFaults f = active_faults_of(t.player());
  ASSERT_EQ(f.count, 1U);
  EXPECT_EQ(f.items[0].until_tick, 0U);
  EXPECT_FALSE(f.items[0].parameters.position_um.has_value());
}

TEST(ScenarioPlayerRuntime, LoadAndAmbientAreRefusedAndCounted) {
  Timeline t(scenario_of({}));
  t.at(0);
  RuntimeEvent step = runtime(EventType::load_step);
  step.parameters.load_n = 2.0;
  EXPECT_FALSE(t.player().queue_runtime(step));
  EXPECT_FALSE(t.player().queue_runtime(runtime(EventType::load_ramp)));
  EXPECT_FALSE(t.player().queue_runtime(runtime(EventType::load_sine)));
  EXPECT_FALSE(t.player().queue_runtime(runtime(EventType::ambient)));
  const ScenarioConditions& c = t.at(1);
  EXPECT_FALSE(c.load_n.has_value());
  EXPECT_FALSE(c.ambient_c.has_value());
  EXPECT_TRUE(c.started.empty());
  EXPECT_EQ(active_faults_of(t.player()).refused, 4U);
  EXPECT_EQ(active_faults_of(t.player()).count, 0U);
}

TEST(ScenarioPlayerRuntime, MoreThanTheMaximumOfRuntimeFaultsAreRefusedAndCounted) {
  Timeline t(scenario_of({}));
  t.at(0);
  for (std::size_t i = 0; i < kMaxActiveFaults + 3; ++i)
    ASSERT_TRUE(t.player().queue_runtime(runtime(EventType::encoder_stuck))) << i;
  t.at(1);
  ActiveFaults f = active_faults_of(t.player());
  EXPECT_EQ(f.count, kMaxActiveFaults);
  EXPECT_EQ(f.refused, 3U);
  // A clear makes room again.
  ASSERT_TRUE(t.player().queue_runtime(runtime_clear(EventType::encoder_stuck)));
  ASSERT_TRUE(t.player().queue_runtime(runtime(EventType::speed_frozen)));
  t.at(2);
  f = active_faults_of(t.player());
  ASSERT_EQ(f.count, 1U);
  EXPECT_EQ(f.items[0].type, EventType::speed_frozen);
  EXPECT_EQ(f.refused, 3U);
}

TEST(ScenarioPlayerRuntime, MoreEventsWaitingThanTheQueueHoldsAreRefusedAndCounted) {
  Timeline t(scenario_of({}));
  t.at(0);
  for (std::size_t i = 0; i < kRuntimeEventCapacity; ++i)
    ASSERT_TRUE(t.player().queue_runtime(runtime_clear(EventType::jam))) << i;
  EXPECT_FALSE(t.player().queue_runtime(runtime(EventType::jam)));
  t.at(1);
  EXPECT_EQ(active_faults_of(t.player()).refused, 1U);
  EXPECT_FALSE(t.at(1).jammed);
  EXPECT_TRUE(t.player().queue_runtime(runtime(EventType::jam)));  // the queue is empty again
  EXPECT_TRUE(t.at(2).jammed);
}

TEST(ScenarioPlayerRuntime, FileEventsOfTheSameTickComeFirst) {
  // The file opens phase A at tick 10; a run-time clear queued for tick 10 comes after it.
  Timeline t(scenario_of({"phase_open@0.001:phase=A"}));
  t.at(9);
  ASSERT_TRUE(t.player().queue_runtime(runtime_clear(EventType::phase_open)));
  const ScenarioConditions& c = t.at(10);
  EXPECT_EQ(c.phase_a_gain, 1.0);
  // Only the file's event is for the loop's log (the API logs what it queues).
  ASSERT_EQ(c.started.size(), 1U);
  EXPECT_EQ(c.started[0], &t.player().scenario().events[0]);
}

TEST(ScenarioPlayerRuntime, RuntimeEventsOfATickStartInTheOrderTheyCame) {
  Timeline t(scenario_of({}));
  t.at(0);
  ASSERT_TRUE(t.player().queue_runtime(runtime_clear(EventType::speed_frozen)));
  ASSERT_TRUE(t.player().queue_runtime(runtime(EventType::speed_frozen)));
  ASSERT_TRUE(t.player().queue_runtime(runtime(EventType::encoder_stuck)));
  ASSERT_TRUE(t.player().queue_runtime(runtime_clear(EventType::encoder_stuck)));
  const ScenarioConditions& c = t.at(1);
  EXPECT_TRUE(c.speed_frozen);     // cleared before it started
  EXPECT_FALSE(c.encoder_stuck);   // cleared after
  EXPECT_TRUE(c.started.empty());  // run-time events are not the loop's to log
}

TEST(ScenarioPlayerRuntime, RuntimeModbusDropCountsAtItsStartTickOnly) {
  Timeline t(scenario_of({}));
  t.at(0);
  RuntimeEvent drop = runtime(EventType::modbus_drop);
  drop.parameters.count = 4;
  ASSERT_TRUE(t.player().queue_runtime(drop));
  EXPECT_EQ(t.at(1).modbus_drops_started, 4U);
  EXPECT_EQ(t.at(2).modbus_drops_started, 0U);
  EXPECT_EQ(active_faults_of(t.player()).count, 0U);  // not a fault that lasts
}

}  // namespace
}  // namespace swum::emu
