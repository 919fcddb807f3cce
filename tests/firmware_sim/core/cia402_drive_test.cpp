#include "core/cia402_drive.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>

#include "../emu_test_support.h"
#include "allocation_count.h"
#include "analysis/steady_state/steady_state.h"
#include "core/emulator_core.h"

namespace swum::emu {
namespace {

using canopen::kControlwordHalt;
using canopen::kErrorCodeHeartbeat;
using canopen::kStatuswordInternalLimit;
using canopen::kStatuswordTargetReached;
using canopen::kStatuswordWarning;

constexpr std::uint16_t kShutdown = 0x0006;
constexpr std::uint16_t kSwitchOn = 0x0007;
constexpr std::uint16_t kEnableOperation = 0x000F;
constexpr std::uint16_t kQuickStop = 0x000B;
constexpr std::uint16_t kDisableVoltage = 0x0000;
constexpr std::uint16_t kFaultReset = 0x0080;

constexpr std::uint16_t kSwitchOnDisabled = 0x0240;
constexpr std::uint16_t kReadyToSwitchOn = 0x0231;
constexpr std::uint16_t kSwitchedOn = 0x0233;
constexpr std::uint16_t kOperationEnabled = 0x0237;
constexpr std::uint16_t kQuickStopActive = 0x0217;
constexpr std::uint16_t kFaultReactionActive = 0x020F;
constexpr std::uint16_t kFault = 0x0208;
// The state's bits of a statusword, without warning, target reached, internal limit and bits 12-13.
std::uint16_t state_bits(std::uint16_t statusword) { return statusword & 0x027F; }

// The calibrated motor (config/li2019.toml) under the drive, in emulated time: the test plays
// the CANopen profile, storing its request before every tick.
struct Bench {
  SharedState shared;
  EmulatorCore core;
  DriveRequest request;

  explicit Bench(CoreConfig config = CoreConfig{}) : core(test::li2019_model(), config, shared) {
    request.active = true;
  }
  const Telemetry& tick() {
    shared.drive_request.store(request);
    return core.tick();
  }
  void run_s(double seconds) {
    const auto n = static_cast<long>(std::llround(seconds / core.tick_s()));
    for (long i = 0; i < n; ++i) tick();
  }
  // Ticks until `done` holds after a tick (returns the emulated seconds it took) or `limit_s`
  // passes (returns infinity).
  double run_until(const std::function<bool(const Telemetry&)>& done, double limit_s) {
    const double start = core.telemetry().sim_time_s;
    while (core.telemetry().sim_time_s - start < limit_s) {
      if (done(tick())) return core.telemetry().sim_time_s - start;
    }
    return std::numeric_limits<double>::infinity();
  }
  // 0x06, 0x07, 0x0F, a tick each, as a master walks the state machine (after the drive's first
  // tick, which takes transition 1 to switch on disabled, as a master waits for it).
  void enable_operation(std::int8_t mode) {
    request.mode = mode;
    if (!cia402().active) tick();
    for (std::uint16_t word : {kShutdown, kSwitchOn, kEnableOperation}) {
      request.controlword = word;
      tick();
    }
  }
  // Profile velocity at 300 mm/s: enabled, and on to target reached (within 0.5 s of emulated time).
  void run_at_300_mm_s() {
    request.target_velocity_um_s = 300000;
    enable_operation(3);
    const double rise_s = run_until(
        [](const Telemetry& t) { return (t.cia402.statusword & kStatuswordTargetReached) != 0; }, 2.0);
    EXPECT_LT(rise_s, 0.5);
  }
  void lose_heartbeat() {  // the profile counts a consumer timeout
    ++request.comm_loss_events;
    tick();
  }
  void fault_reset() {  // the profile counts the rising edge of bit 7
    request.controlword = kFaultReset;
    ++request.fault_reset_edges;
    tick();
  }
  [[nodiscard]] const protocol::Cia402Values& cia402() const { return core.telemetry().cia402; }
  [[nodiscard]] std::uint16_t statusword() const { return cia402().statusword; }
  [[nodiscard]] bool target_reached() const { return (statusword() & kStatuswordTargetReached) != 0; }
  [[nodiscard]] double speed_mm_s() const { return core.telemetry().speed_m_s * 1e3; }
};

bool reached(const Telemetry& t) { return (t.cia402.statusword & kStatuswordTargetReached) != 0; }

TEST(Cia402Drive, InactiveRequestLeavesTheAmplifierToTheQueue) {
  Bench b;
  b.request.active = false;
  b.request.controlword = kEnableOperation;
  b.request.mode = 3;
  b.request.target_velocity_um_s = 300000;
  b.run_s(0.05);
  EXPECT_FALSE(b.cia402().active);
  EXPECT_EQ(b.statusword(), 0);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::disabled);
  EXPECT_EQ(b.core.amplifier().applied_commands(), 0U);
  EXPECT_EQ(b.core.drive().commands_issued(), 0U);
}

TEST(Cia402Drive, ControlwordSequenceWalksTheStatesAndOnlyOperationEnabledDrives) {
  Bench b;
  b.tick();
  EXPECT_TRUE(b.cia402().active);
  EXPECT_EQ(b.statusword(), kSwitchOnDisabled);
  EXPECT_EQ(b.cia402().state, static_cast<std::uint8_t>(Cia402State::switch_on_disabled));
  b.request.controlword = kEnableOperation;  // from switch on disabled: needs "shutdown" first
  b.run_s(0.01);
  EXPECT_EQ(b.statusword(), kSwitchOnDisabled);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::disabled);
  b.request.controlword = kShutdown;
  b.tick();
  EXPECT_EQ(b.statusword(), kReadyToSwitchOn);
  b.request.controlword = kSwitchOn;
  b.tick();
  EXPECT_EQ(b.statusword(), kSwitchedOn);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::disabled);
  b.request.controlword = kEnableOperation;
  b.tick();
  EXPECT_EQ(state_bits(b.statusword()), kOperationEnabled);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::enabled);
  b.request.controlword = kSwitchOn;  // disable operation (5)
  b.tick();
  EXPECT_EQ(b.statusword(), kSwitchedOn);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::disabled);
  b.request.controlword = kShutdown;  // 6
  b.tick();
  EXPECT_EQ(b.statusword(), kReadyToSwitchOn);
  b.request.controlword = kEnableOperation;  // switch on + enable operation (3 + 4) in one tick
  b.tick();
  EXPECT_EQ(state_bits(b.statusword()), kOperationEnabled);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::enabled);
  b.request.controlword = kDisableVoltage;  // 9
  b.tick();
  EXPECT_EQ(b.statusword(), kSwitchOnDisabled);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::disabled);
  EXPECT_EQ(b.core.drive().commands_refused(), 0U);
}

// The case: 0x06, 0x07, 0x0F in profile velocity at 300 mm/s on the calibrated motor,
// then a 1.5 N load step: the speed loop and the tracker inside the drive hold the window.
TEST(Cia402Drive, ProfileVelocityReaches300MmSAndHoldsItThroughA1Point5NLoadStep) {
  Bench b;
  b.core.set_scenario(test::scenario_of({"load_step@0.6:load_n=1.5"}), nullptr);
  b.request.target_velocity_um_s = 300000;
  b.enable_operation(3);
  const double rise_s = b.run_until(reached, 2.0);
  // The ramp alone takes 0.15 s at 2 m/s^2; the window's 50 ms and the loop's settling follow.
  EXPECT_LT(rise_s, 0.5);
  EXPECT_GT(rise_s, 0.15 + 0.05);
  EXPECT_NEAR(b.speed_mm_s(), 300.0, 10.0);
  EXPECT_NEAR(b.cia402().velocity_demand_m_s, 0.300, 1e-12);
  EXPECT_EQ(b.statusword(), kOperationEnabled | kStatuswordTargetReached);
  b.run_s(0.55 - b.core.telemetry().sim_time_s);
  const Telemetry unloaded = b.core.telemetry();
  EXPECT_TRUE(reached(unloaded));
  EXPECT_NEAR(unloaded.speed_m_s * 1e3, 300.0, 1.0);
  // The tracker holds phase A's motional current phase at 0x2031's 15 deg, near the speed peak.
  EXPECT_NEAR(unloaded.electrical.motional_phase_a_deg, 15.0, 1.0);
  EXPECT_NEAR(unloaded.cia402.tracking_frequency_hz, unloaded.output.frequency_hz, 1e-9);
  EXPECT_GT(unloaded.output.frequency_hz, 39800.0);
  EXPECT_LT(unloaded.output.frequency_hz, 40200.0);
  EXPECT_EQ(unloaded.output.phase_deg, 90.0);
  EXPECT_NEAR(unloaded.cia402.terminal_amplitude_v, unloaded.output.amplitude_v, 1e-12);  // convention "amplitude"

  // The load: the speed leaves the window, the loop raises the amplitude and is back in it.
  const double lost_s = b.run_until([](const Telemetry& t) { return !reached(t); }, 0.1);
  EXPECT_LT(b.core.telemetry().sim_time_s, 0.62);
  EXPECT_LT(lost_s, 0.1);
  const double dip_mm_s = [&] {
    double lowest = 1e9;
    for (int i = 0; i < 300; ++i) lowest = std::min(lowest, b.tick().speed_m_s * 1e3);
    return lowest;
  }();
  EXPECT_LT(dip_mm_s, 290.0);
  EXPECT_GT(dip_mm_s, 200.0);
  const double recovered_s = b.run_until(reached, 1.0);
  EXPECT_LT(recovered_s, 0.3);
  b.run_s(0.2);
  const Telemetry& loaded = b.core.telemetry();
  EXPECT_EQ(loaded.output.load_n, 1.5);
  EXPECT_TRUE(reached(loaded));
  EXPECT_NEAR(loaded.speed_m_s * 1e3, 300.0, 1.0);
  EXPECT_GT(loaded.output.amplitude_v, unloaded.output.amplitude_v + 10.0);  // more voltage for the same speed
  EXPECT_NEAR(loaded.electrical.motional_phase_a_deg, 15.0, 1.0);
  EXPECT_EQ(loaded.state, AmpState::enabled);
  EXPECT_EQ(b.core.drive().commands_refused(), 0U);
}

TEST(Cia402Drive, NegativeTargetMovesTheOtherWayLockedOnPhaseB) {
  Bench b;
  b.request.target_velocity_um_s = -300000;
  b.enable_operation(3);
  const double start_position_m = b.core.telemetry().position_m;
  EXPECT_LT(b.run_until(reached, 2.0), 0.5);
  b.run_s(0.2);
  const Telemetry& t = b.core.telemetry();
  EXPECT_TRUE(reached(t));
  EXPECT_NEAR(t.speed_m_s * 1e3, -300.0, 1.0);
  EXPECT_LT(t.position_m - start_position_m, -0.05);  // moved back by well over 5 cm
  EXPECT_EQ(t.output.phase_deg, -90.0);
  // Reversed, phase B leads: its motional phase is the one held at the set-point.
  EXPECT_NEAR(t.electrical.motional_phase_b_deg, 15.0, 1.0);
  EXPECT_NEAR(t.cia402.velocity_demand_m_s, -0.300, 1e-12);
}

TEST(Cia402Drive, ReversesThroughZeroOnTheFly) {
  Bench b;
  b.run_at_300_mm_s();
  b.request.target_velocity_um_s = -300000;
  // 0.6 m/s of demand at 2 m/s^2 both ways: 0.3 s, then the window's time.
  const double s = b.run_until(reached, 2.0);
  EXPECT_GT(s, 0.3 + 0.05);
  EXPECT_LT(s, 0.45);  // 0.355 s: the loop follows the ramp through zero
  EXPECT_NEAR(b.speed_mm_s(), -300.0, 10.0);
  EXPECT_EQ(b.core.telemetry().output.phase_deg, -90.0);
}

TEST(Cia402Drive, HaltDeceleratesAtTheProfileDecelerationAndStaysEnabled) {
  Bench b;
  b.request.profile_deceleration_um_s2 = 1000000;  // 1 m/s^2: 0.3 s to stop
  b.run_at_300_mm_s();
  b.request.controlword = kEnableOperation | kControlwordHalt;
  b.run_s(0.1);
  EXPECT_NEAR(b.cia402().velocity_demand_m_s, 0.200, 0.002);  // 0.1 s at 1 m/s^2
  EXPECT_FALSE(b.target_reached());
  const double stopped_s = b.run_until([](const Telemetry& t) { return t.cia402.velocity_demand_m_s == 0.0; }, 1.0);
  EXPECT_NEAR(stopped_s, 0.2, 0.002);
  EXPECT_LT(b.run_until(reached, 0.5), 0.2);  // target reached: standstill within the window
  EXPECT_NEAR(b.speed_mm_s(), 0.0, 10.0);
  EXPECT_EQ(state_bits(b.statusword()), kOperationEnabled);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::enabled);
  EXPECT_EQ(b.core.telemetry().output.amplitude_v, 0.0);
  b.request.controlword = kEnableOperation;  // halt released: off again to the target
  EXPECT_LT(b.run_until(reached, 2.0), 0.5);
  EXPECT_NEAR(b.speed_mm_s(), 300.0, 10.0);
}

// Quick stop (0x0B) with each supported 0x605A option from 300 mm/s.
struct QuickStopRun {
  double demand_zero_s = 0.0;  // from the quick stop to a velocity demand of 0
  std::uint16_t statusword_after = 0;
  AmpState amplifier_after = AmpState::disabled;
};
QuickStopRun quick_stop_from_300(std::int16_t option, Bench& b) {
  b.request.quick_stop_option = option;
  b.run_at_300_mm_s();
  b.request.controlword = kQuickStop;
  QuickStopRun run;
  run.demand_zero_s = b.run_until([](const Telemetry& t) { return t.cia402.velocity_demand_m_s == 0.0; }, 1.0);
  b.run_s(0.1);
  run.statusword_after = b.statusword();
  run.amplifier_after = b.core.amplifier().state();
  return run;
}

TEST(Cia402Drive, QuickStopOption2RampsAtTheQuickStopDecelerationThenSwitchesOnDisabled) {
  Bench b;
  const QuickStopRun r = quick_stop_from_300(2, b);
  EXPECT_NEAR(r.demand_zero_s, 0.030, 0.002);  // 0.3 m/s at 10 m/s^2 (0x6085)
  EXPECT_EQ(r.statusword_after, kSwitchOnDisabled);
  EXPECT_EQ(r.amplifier_after, AmpState::disabled);
  EXPECT_NEAR(b.speed_mm_s(), 0.0, 5.0);
}

TEST(Cia402Drive, QuickStopOption1RampsAtTheProfileDeceleration) {
  Bench b;
  const QuickStopRun r = quick_stop_from_300(1, b);
  EXPECT_NEAR(r.demand_zero_s, 0.150, 0.002);  // 0.3 m/s at 2 m/s^2 (0x6084)
  EXPECT_EQ(r.statusword_after, kSwitchOnDisabled);
  EXPECT_EQ(r.amplifier_after, AmpState::disabled);
}

TEST(Cia402Drive, QuickStopOption0SwitchesTheDriveOffAtOnce) {
  Bench b;
  b.request.quick_stop_option = 0;
  b.run_at_300_mm_s();
  b.request.controlword = kQuickStop;
  b.tick();
  EXPECT_EQ(b.statusword(), kSwitchOnDisabled);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::disabled);
  EXPECT_EQ(b.core.telemetry().output.amplitude_v, 0.0);
  EXPECT_GT(b.speed_mm_s(), 250.0);  // the mover coasts: no ramp
}

TEST(Cia402Drive, QuickStopOptions5And6StayInQuickStopActiveUntilEnableOperation) {
  for (std::int16_t option : {5, 6}) {
    Bench b;
    const QuickStopRun r = quick_stop_from_300(option, b);
    EXPECT_NEAR(r.demand_zero_s, option == 5 ? 0.150 : 0.030, 0.002) << option;
    EXPECT_EQ(state_bits(r.statusword_after), kQuickStopActive) << option;
    EXPECT_NE(r.statusword_after & kStatuswordTargetReached, 0) << option;  // stopped
    EXPECT_EQ(r.amplifier_after, AmpState::enabled) << option;              // powered at standstill
    EXPECT_EQ(b.core.telemetry().output.amplitude_v, 0.0);
    b.request.controlword = kEnableOperation;  // 16
    b.tick();
    EXPECT_EQ(state_bits(b.statusword()), kOperationEnabled) << option;
    EXPECT_LT(b.run_until(reached, 2.0), 0.5) << option;
    EXPECT_NEAR(b.speed_mm_s(), 300.0, 10.0) << option;
  }
}

TEST(Cia402Drive, OverTemperatureFaultsWith0x4310AndAResetEdgeReturnsToSwitchOnDisabled) {
  Bench b;
  b.core.set_scenario(test::scenario_of({"over_temperature@0.3"}), nullptr);
  b.request.target_velocity_um_s = 300000;
  b.enable_operation(3);
  b.run_until([](const Telemetry& t) { return t.state == AmpState::fault; }, 1.0);
  EXPECT_NEAR(b.core.telemetry().sim_time_s, 0.3, 0.0002);
  EXPECT_EQ(b.core.telemetry().fault, FaultCode::over_temperature);
  // The amplifier tripped in the scenario's tick, after the drive's turn: the drive reacts at the
  // next boundary, one tick in fault reaction active (the output is off already), then fault.
  EXPECT_EQ(b.statusword(), kOperationEnabled | kStatuswordTargetReached);
  b.tick();
  EXPECT_EQ(b.statusword(), kFaultReactionActive);
  EXPECT_EQ(b.cia402().error_code, 0x4310);
  b.tick();
  EXPECT_EQ(b.statusword(), kFault);  // bit 3 fault
  EXPECT_NE(b.statusword() & 0x0008, 0);
  EXPECT_EQ(b.cia402().error_code, 0x4310);
  EXPECT_EQ(b.core.telemetry().output.amplitude_v, 0.0);
  b.run_s(0.2);
  EXPECT_NEAR(b.speed_mm_s(), 0.0, 2.0);  // no drive: the mover stopped
  EXPECT_EQ(b.statusword(), kFault);
  // Bit 7 held without a new edge, and other commands: still fault.
  b.request.controlword = kFaultReset;
  b.run_s(0.01);
  b.request.controlword = kEnableOperation;
  b.run_s(0.01);
  EXPECT_EQ(b.statusword(), kFault);
  b.fault_reset();
  EXPECT_EQ(b.statusword(), kSwitchOnDisabled);
  EXPECT_EQ(b.cia402().error_code, 0);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::disabled);
  EXPECT_EQ(b.core.amplifier().fault(), FaultCode::none);
}

TEST(Cia402Drive, PhaseShortAndNumericalBlowUpMapToTheirCodes) {
  {
    Bench b;
    b.core.set_scenario(test::scenario_of({"phase_short@0.05:phase=A"}), nullptr);
    b.request.target_velocity_um_s = 300000;
    b.enable_operation(3);
    b.run_until([](const Telemetry& t) { return t.cia402.statusword == kFault; }, 0.2);
    EXPECT_EQ(b.statusword(), kFault);
    EXPECT_EQ(b.cia402().error_code, 0x2320);
  }
  {
    Bench b;
    b.request.target_velocity_um_s = 300000;
    b.enable_operation(3);
    b.run_s(0.05);
    MotorState s = b.core.simulator().state();
    s.q1_m = std::numeric_limits<double>::quiet_NaN();
    b.core.simulator().set_state(s);
    b.run_until([](const Telemetry& t) { return t.cia402.statusword == kFault; }, 0.01);
    EXPECT_EQ(b.statusword(), kFault);
    EXPECT_EQ(b.cia402().error_code, 0x6100);
    b.fault_reset();
    EXPECT_EQ(b.statusword(), kSwitchOnDisabled);
  }
}

// Heartbeat loss (the profile counts consumer timeouts) reacts per 0x6007.
TEST(Cia402Drive, HeartbeatLossOption1FaultsWith0x8130) {
  Bench b;
  b.request.abort_connection_option = 1;
  b.request.target_velocity_um_s = 300000;
  b.enable_operation(3);
  b.run_s(0.1);
  b.lose_heartbeat();
  EXPECT_EQ(b.statusword(), kFaultReactionActive);
  EXPECT_EQ(b.cia402().error_code, kErrorCodeHeartbeat);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::disabled);  // the drive's own fault: the amplifier is off
  b.tick();
  EXPECT_EQ(b.statusword(), kFault);
  b.run_s(0.01);
  EXPECT_EQ(b.statusword(), kFault);
  b.fault_reset();
  EXPECT_EQ(b.statusword(), kSwitchOnDisabled);
  EXPECT_EQ(b.cia402().error_code, 0);
  b.enable_operation(3);  // and runs again
  EXPECT_LT(b.run_until(reached, 2.0), 0.5);
}

// 0x6007 reacts on a running drive only: a master's NMT reset communication at its own start
// (the profile counts it as a connection abort) must not fault a drive at rest.
TEST(Cia402Drive, AConnectionAbortAtRestChangesNothing) {
  Bench b;
  b.request.abort_connection_option = 1;
  b.tick();
  ASSERT_EQ(b.statusword(), kSwitchOnDisabled);
  b.lose_heartbeat();
  EXPECT_EQ(b.statusword(), kSwitchOnDisabled);
  EXPECT_EQ(b.cia402().error_code, 0);
  b.enable_operation(3);  // and the drive still runs
  EXPECT_EQ(state_bits(b.statusword()), state_bits(kOperationEnabled));
}

TEST(Cia402Drive, HeartbeatLossOption2DisablesVoltage) {
  Bench b;
  b.request.abort_connection_option = 2;
  b.request.target_velocity_um_s = 300000;
  b.enable_operation(3);
  b.run_s(0.1);
  b.lose_heartbeat();
  EXPECT_EQ(b.statusword(), kSwitchOnDisabled);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::disabled);
  b.run_s(0.05);  // the latched 0x0F does not enable again
  EXPECT_EQ(b.statusword(), kSwitchOnDisabled);
  EXPECT_EQ(b.cia402().error_code, 0);
}

TEST(Cia402Drive, HeartbeatLossOption3QuickStopsAndALatchedEnableOperationDoesNotRestart) {
  Bench b;
  b.request.abort_connection_option = 3;
  b.request.quick_stop_option = 6;  // stay in quick stop active
  b.run_at_300_mm_s();
  b.lose_heartbeat();
  EXPECT_EQ(state_bits(b.statusword()), kQuickStopActive);
  b.run_s(0.1);
  EXPECT_EQ(state_bits(b.statusword()), kQuickStopActive);  // 0x0F still latched: no transition 16
  EXPECT_EQ(b.cia402().velocity_demand_m_s, 0.0);
  EXPECT_NEAR(b.speed_mm_s(), 0.0, 5.0);
  b.request.controlword = kQuickStop;  // the master is back: it commands again
  b.tick();
  b.request.controlword = kEnableOperation;
  b.tick();
  EXPECT_EQ(state_bits(b.statusword()), kOperationEnabled);
}

TEST(Cia402Drive, HeartbeatLossOption0DoesNothing) {
  Bench b;
  b.request.abort_connection_option = 0;
  b.run_at_300_mm_s();
  b.request.comm_loss_events += 3;
  b.run_s(0.1);
  EXPECT_EQ(b.statusword(), kOperationEnabled | kStatuswordTargetReached);
  EXPECT_NEAR(b.speed_mm_s(), 300.0, 10.0);
}

// Mode -1: the amplifier's set-points straight from 0x2001-0x2005, the terminal amplitude in mV
// as the model's "amplitude_v" input (convention "amplitude": the same volts).
TEST(Cia402Drive, OpenLoopDrivesTheCommandedFrequencyAmplitudeAndPhase) {
  Bench b;
  b.request.frequency_mhz = 40000000;
  b.request.amplitude_mv = 400000;
  b.request.phase_cdeg = 9000;
  b.enable_operation(-1);
  EXPECT_EQ(b.cia402().mode_display, -1);
  b.run_s(0.1);
  const Telemetry& t = b.core.telemetry();
  EXPECT_EQ(t.output.frequency_hz, 40000.0);
  EXPECT_EQ(t.output.amplitude_v, 400.0);
  EXPECT_EQ(t.output.phase_deg, 90.0);
  EXPECT_EQ(t.setpoints.amplitude_slew_v_per_s, 100000.0);
  EXPECT_EQ(t.setpoints.frequency_slew_hz_per_s, 1000000.0);
  EXPECT_EQ(t.cia402.terminal_amplitude_v, 400.0);
  EXPECT_TRUE(reached(t));  // at the set-points
  // The open-loop steady state of the model at the same drive.
  const SteadyStateResult ref = run_to_steady_state(test::li2019_model(), OperatingPoint{400, 40000, 0, 90});
  ASSERT_TRUE(ref.ok);
  EXPECT_NEAR(t.speed_m_s * 1e3, ref.speed_mm_s, 0.03 * std::abs(ref.speed_mm_s) + 2.0);
  // Reversed phase, new frequency: the drive follows the request.
  b.request.phase_cdeg = -9000;
  b.request.frequency_mhz = 40500000;
  b.run_s(0.1);
  EXPECT_EQ(b.core.telemetry().output.phase_deg, -90.0);
  EXPECT_EQ(b.core.telemetry().output.frequency_hz, 40500.0);
  EXPECT_LT(b.speed_mm_s(), -50.0);
  EXPECT_EQ(b.core.drive().commands_refused(), 0U);
}

TEST(Cia402Drive, OpenLoopHoldsOutOfRangeSetPointsAtTheLimitsAsInternalLimit) {
  Bench b;
  b.request.frequency_mhz = 60000000;  // above the amplifier's 50 kHz
  b.request.amplitude_mv = 100000;
  b.enable_operation(-1);
  b.run_s(0.01);
  EXPECT_EQ(b.core.telemetry().setpoints.frequency_hz, 50000.0);
  EXPECT_NE(b.statusword() & kStatuswordInternalLimit, 0);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::enabled);
  EXPECT_EQ(b.core.drive().commands_refused(), 0U);
  b.request.frequency_mhz = 40000000;
  b.run_s(0.01);
  EXPECT_EQ(b.statusword() & kStatuswordInternalLimit, 0);
}

TEST(Cia402Drive, ModeNoneAndUnsupportedModesDriveZeroVolts) {
  for (int mode : {0, 1, 7}) {
    Bench b;
    b.request.amplitude_mv = 300000;  // what mode -1 would drive
    b.request.target_velocity_um_s = 300000;
    b.enable_operation(static_cast<std::int8_t>(mode));
    b.run_s(0.05);
    EXPECT_EQ(state_bits(b.statusword()), kOperationEnabled) << mode;
    EXPECT_EQ(b.core.amplifier().state(), AmpState::enabled) << mode;
    EXPECT_EQ(b.core.telemetry().output.amplitude_v, 0.0) << mode;
    EXPECT_EQ(b.cia402().mode_display, 0) << mode;
    EXPECT_EQ((b.statusword() & kStatuswordWarning) != 0, mode != 0) << mode;  // a mode it does not have
  }
}

TEST(Cia402Drive, ModeDisplayFollowsTheSupportedModeAndAModeChangeRestartsTheLoop) {
  Bench b;
  b.request.target_velocity_um_s = 300000;
  b.request.frequency_mhz = 40000000;
  b.request.amplitude_mv = 100000;
  b.enable_operation(3);
  EXPECT_EQ(b.cia402().mode_display, 3);
  ASSERT_LT(b.run_until(reached, 2.0), 0.5);
  b.request.mode = -1;
  b.run_s(0.05);
  EXPECT_EQ(b.cia402().mode_display, -1);
  EXPECT_EQ(b.core.telemetry().setpoints.amplitude_v, 100.0);
  b.request.mode = 3;  // back: the demand starts from the speed the mover has
  b.tick();
  EXPECT_EQ(b.cia402().mode_display, 3);
  EXPECT_LT(b.cia402().velocity_demand_m_s, 0.2);
  EXPECT_LT(b.run_until(reached, 2.0), 0.5);
}

// In CANopen mode the master is silent towards the amplifier: the drive's own commands keep the
// amplifier's command watchdog (0.1 s) fed, in every mode.
TEST(Cia402Drive, TheDriveFeedsTheAmplifierWatchdog) {
  for (int mode : {3, -1, 0}) {
    Bench b;
    ASSERT_EQ(b.core.amplifier().config().watchdog_s, 0.1);
    b.request.target_velocity_um_s = 100000;
    b.request.amplitude_mv = 100000;
    b.enable_operation(static_cast<std::int8_t>(mode));
    b.run_s(1.0);
    EXPECT_EQ(b.core.amplifier().state(), AmpState::enabled) << mode;
    EXPECT_EQ(state_bits(b.statusword()), kOperationEnabled) << mode;
    EXPECT_EQ(b.core.drive().control_cycle_ticks(), 10U);
  }
}

TEST(Cia402Drive, EnableLineLowRefusesOperationAndDropsToSwitchOnDisabled) {
  Bench b;
  b.shared.enable_line.store(false);
  b.tick();  // the amplifier reads the line at its tick
  b.enable_operation(3);
  EXPECT_EQ(b.statusword(), kSwitchOnDisabled | kStatuswordWarning);
  EXPECT_EQ(b.core.amplifier().state(), AmpState::disabled);
  b.shared.enable_line.store(true);
  b.enable_operation(3);
  EXPECT_EQ(state_bits(b.statusword()), kOperationEnabled);
  b.run_s(0.05);
  b.shared.enable_line.store(false);  // the line drops while the drive runs
  b.run_s(0.001);
  EXPECT_EQ(b.statusword(), kSwitchOnDisabled | kStatuswordWarning);
}

TEST(Cia402Drive, DeactivationSwitchesTheAmplifierOff) {
  Bench b;
  b.request.amplitude_mv = 100000;
  b.enable_operation(-1);
  b.run_s(0.01);
  ASSERT_EQ(b.core.amplifier().state(), AmpState::enabled);
  b.request.active = false;
  b.tick();
  EXPECT_EQ(b.core.amplifier().state(), AmpState::disabled);
  EXPECT_FALSE(b.cia402().active);
}

// The drive's commands reach the tick observer as the queue's do (a trace holds them all).
struct CountingObserver final : TickObserver {
  std::uint64_t commands = 0;
  std::uint64_t can_commands = 0;
  void on_command(std::uint64_t, const Command& c) override {
    ++commands;
    if (c.source == CommandSource::can) ++can_commands;
  }
  void on_enable_line(std::uint64_t, bool) override {}
  void on_telemetry(const Telemetry&) override {}
};

TEST(Cia402Drive, TheObserverSeesEveryCommandTheDriveApplies) {
  Bench b;
  CountingObserver observer;
  b.core.set_observer(&observer);
  b.request.target_velocity_um_s = 100000;
  b.enable_operation(3);
  b.run_s(0.1);
  EXPECT_EQ(observer.commands, b.core.drive().commands_issued());
  EXPECT_EQ(observer.can_commands, observer.commands);
  EXPECT_EQ(b.core.amplifier().applied_commands(), observer.commands);
  EXPECT_GE(observer.commands, 100U);  // one per 1 ms cycle, and the enable
}

// 0x2002 and 0x2005 are the terminal amplitude and its slew, the amplifier's own input: one to
// one, whatever motor runs (no factor of two anywhere). The drive alone on an amplifier, no model.
TEST(Cia402Drive, TheAmplitudeObjectsAreTheAmplifierInputOneToOne) {
  Cia402DriveConfig config;
  Cia402Drive drive(config);
  AmplifierConfig amplifier_config;
  Amplifier amplifier(amplifier_config);
  DriveRequest r;
  r.active = true;
  r.mode = -1;
  r.amplitude_mv = 150000;
  r.amplitude_slew_v_per_s = 1000;
  Telemetry last;
  std::uint64_t tick = 0;
  for (std::uint16_t word : {kShutdown, kShutdown, kSwitchOn, kEnableOperation}) {
    r.controlword = word;
    drive.tick(r, amplifier, last, tick);
    last.output = drive_values(amplifier.tick(tick, true));
    ++tick;
  }
  EXPECT_EQ(drive.state(), Cia402State::operation_enabled);
  EXPECT_EQ(amplifier.setpoints().amplitude_v, 150.0);
  EXPECT_EQ(amplifier.setpoints().amplitude_slew_v_per_s, 1000.0);
  EXPECT_GT(amplifier.output().amplitude_v, 0.0);
  EXPECT_EQ(drive.values(amplifier.output()).terminal_amplitude_v, amplifier.output().amplitude_v);
}

TEST(Cia402Drive, RefusesAConfigurationItCannotRun) {
  Cia402DriveConfig bad;
  bad.control_cycle_s = 0.0;
  EXPECT_THROW(Cia402Drive{bad}, std::invalid_argument);
  bad = {};
  bad.tracker_cycles = 0;
  EXPECT_THROW(Cia402Drive{bad}, std::invalid_argument);
  bad = {};
  bad.drive_phase_deg = 0.0;
  EXPECT_THROW(Cia402Drive{bad}, std::invalid_argument);
  bad = {};
  bad.tracker.phase_gain_hz_per_deg = 0.0;  // the tracker's own check
  EXPECT_THROW(Cia402Drive{bad}, std::invalid_argument);
}

TEST(Cia402Drive, ControlCycleIsDerivedFromTheTickRate) {
  Cia402DriveConfig config;
  config.tick_hz = 20000.0;
  EXPECT_EQ(Cia402Drive(config).control_cycle_ticks(), 20U);
  config.tick_hz = 500.0;  // slower than the cycle: every tick
  EXPECT_EQ(Cia402Drive(config).control_cycle_ticks(), 1U);
}

// A tick allocates nothing while the drive starts, tracks, takes a new tracker set-point,
// reverses, quick-stops, faults and is reset (the tracker is restarted in place).
TEST(Cia402Drive, TicksAllocateNothing) {
  auto b = std::make_unique<Bench>();
  b->request.target_velocity_um_s = 300000;
  b->request.quick_stop_option = 6;
  b->request.abort_connection_option = 1;
  b->tick();  // first use of everything outside the drive
  const long before = swum::test::allocation_count();
  b->enable_operation(3);
  b->run_s(0.3);
  b->request.motional_phase_setpoint_cdeg = 500;
  b->run_s(0.1);
  b->request.target_velocity_um_s = -300000;
  b->run_s(0.4);
  b->request.controlword = kQuickStop;
  b->run_s(0.1);
  b->request.controlword = kEnableOperation;
  b->run_s(0.1);
  ++b->request.comm_loss_events;
  b->run_s(0.01);
  b->fault_reset();
  b->request.mode = -1;
  b->enable_operation(-1);
  b->run_s(0.05);
  EXPECT_EQ(swum::test::allocation_count() - before, 0);
  EXPECT_EQ(b->statusword() & 0x006F, 0x0027);  // it did run to the end: operation enabled
}

}  // namespace
}  // namespace swum::emu
