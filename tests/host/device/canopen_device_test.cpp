// The host's CANopen master (host/device/canopen_device.h) against the real slave in-process:
// swum-emu's CanTransport with the CANopen profile and the CiA 402 drive of an EmulatorCore on the
// li2019 motor, on the fake bus, stepped in lockstep or run on the wall clock. A spy on the bus
// keeps every frame, so the configuration is checked byte by byte (CiA 301's procedure), the
// controlword walk frame by frame, and the telemetry against what the core published.
#include "device/canopen_device.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "../../firmware_sim/emu_test_support.h"
#include "analysis/steady_state/steady_state.h"
#include "control/speed_control.h"
#include "core/emulator_core.h"
#include "core/lockstep_clock.h"
#include "core/realtime_loop.h"
#include "device/device_sweep.h"
#include "fake_can_bus.h"
#include "object_dictionary.h"
#include "sdo_server.h"
#include "transports/can_transport.h"
#include "transports/canopen_profile.h"

namespace swum::host {
namespace {

constexpr std::uint8_t kNode = 3;
constexpr std::uint32_t kSyncTicks = 10;  // swum-emu's default --sync-ticks: 1 ms at 10 kHz
const DeviceTimeouts kTimeouts{std::chrono::milliseconds(2000), std::chrono::milliseconds(2000)};

using Bytes = std::vector<std::uint8_t>;
Bytes bytes_of(const protocol::CanFrame& f) { return {f.data.begin(), f.data.begin() + f.dlc}; }

// swum-emu --can-profile cia402 --node 3 on the li2019 motor, in-process.
class Emulator {
 public:
  Emulator(bool lockstep, emu::Scenario scenario = {}) {
    emu::CoreConfig config;
    config.external_clock = lockstep;
    if (lockstep) shared_.lockstep = &clock_;
    core_ = std::make_unique<emu::EmulatorCore>(emu::test::li2019_model(), config, shared_);
    if (!scenario.events.empty()) core_->set_scenario(std::move(scenario), nullptr);
    auto profile = std::make_unique<emu::CanopenProfile>(emu::CanopenProfileConfig{kNode, {}, -1}, shared_);
    emu::CanTransportConfig can;
    can.sync_ticks = kSyncTicks;
    transport_ = std::make_unique<emu::CanTransport>(network->attach("emu"), nullptr, std::move(profile), can, shared_,
                                                     emu::AmplifierLimits{});
    transport_->start();
    loop_ = std::thread([this, lockstep] {
      if (lockstep) {
        emu::LockstepLoop(*core_, clock_, {}).run(stop_);
      } else {
        emu::RealtimeLoop(*core_, emu::LoopConfig{}).run(stop_);
      }
    });
  }
  ~Emulator() {
    stop_ = true;
    loop_.join();  // a lockstep loop closes its clock: a SYNC waiting for ticks is answered
    transport_->stop();
  }
  emu::Telemetry telemetry() { return shared_.telemetry.load(); }
  emu::DriveRequest request() { return shared_.drive_request.load(); }
  // The core's telemetry once `ticks` ticks have run (a lockstep step returns before its cycle ends).
  emu::Telemetry after(std::uint64_t ticks) {
    EXPECT_TRUE(emu::test::eventually([&] { return telemetry().tick >= ticks; }));
    return telemetry();
  }

  std::shared_ptr<io::FakeCanNetwork> network = io::FakeCanNetwork::create();
  std::unique_ptr<io::FakeCanBus> spy = network->attach("spy");  // sees every frame of the others

 private:
  emu::SharedState shared_;
  emu::LockstepClock clock_;
  std::unique_ptr<emu::EmulatorCore> core_;
  std::unique_ptr<emu::CanTransport> transport_;
  std::atomic<bool> stop_{false};
  std::thread loop_;
};

// Everything the spy has received so far.
std::vector<protocol::CanFrame> frames(io::FakeCanBus& spy) {
  std::vector<protocol::CanFrame> out;
  io::CanFrame f;
  while (spy.receive(f, std::chrono::milliseconds(20)).ok()) out.push_back(f);
  return out;
}
std::vector<protocol::CanFrame> with_id(const std::vector<protocol::CanFrame>& all, std::uint32_t id) {
  std::vector<protocol::CanFrame> out;
  for (const auto& f : all)
    if (f.id == id) out.push_back(f);
  return out;
}
// The controlwords of the host's RPDO2s, in order.
std::vector<std::uint16_t> controlwords(const std::vector<protocol::CanFrame>& all) {
  std::vector<std::uint16_t> out;
  for (const auto& f : with_id(all, 0x300 + kNode))
    out.push_back(static_cast<std::uint16_t>(f.data[0] | f.data[1] << 8));
  return out;
}

CanopenNode lockstep_node() {
  CanopenNode n;
  n.sync_ticks = kSyncTicks;
  return n;
}

std::unique_ptr<CanopenDevice> open(Emulator& emu, const CanopenNode& settings = lockstep_node()) {
  return std::make_unique<CanopenDevice>(emu.network->attach("host"), kNode, settings, kTimeouts);
}

// Lockstep cycles of `action` until the telemetry shows `state` (at most `cycles`): the last telemetry.
DeviceTelemetry step_until(CanopenDevice& device, const DriveSetpoint& s, DeviceAction action, protocol::AmpState state,
                           int cycles, const DriveSlew& slew = {}) {
  DeviceTelemetry t = device.step(s, slew, action, kSyncTicks);
  for (int i = 1; i < cycles && !t.is(state); ++i) t = device.step(s, slew, action, kSyncTicks);
  return t;
}

TEST(CanopenDevice, OpensTheNodeWithCia301sProcedure) {
  Emulator emu(true);
  const auto device = open(emu);
  const std::vector<protocol::CanFrame> all = frames(*emu.spy);
  // NMT enter pre-operational (no reset: that would be a connection abort, CiA 402 0x6007).
  std::size_t boot = 0;
  while (boot < all.size() && !(all[boot].id == 0x000 && bytes_of(all[boot]) == Bytes{0x80, kNode})) ++boot;
  ASSERT_LT(boot, all.size()) << "no NMT enter pre-operational";
  for (const auto& f : all) EXPECT_FALSE(f.id == 0x000 && (f.data[0] == 0x81 || f.data[0] == 0x82)) << "a reset";
  // Every SDO request after it, exactly; no answer was an abort.
  std::vector<Bytes> requests;
  for (std::size_t i = boot; i < all.size(); ++i) {
    if (all[i].id == 0x600 + kNode) requests.push_back(bytes_of(all[i]));
    if (all[i].id == 0x580 + kNode) {
      EXPECT_NE(all[i].data[0], 0x80) << "an SDO abort";
    }
  }
  const std::vector<Bytes> expected = {
      {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0},              // upload device type
      {0x40, 0x02, 0x65, 0x00, 0, 0, 0, 0},              // upload supported modes
      {0x2F, 0x60, 0x60, 0x00, 0xFF, 0, 0, 0},           // 0x6060 = -1
      {0x23, 0x00, 0x18, 0x01, 0x83, 0x01, 0x00, 0x80},  // TPDO1 invalid
      {0x2F, 0x00, 0x1A, 0x00, 0x00, 0, 0, 0},           // mapping count 0
      {0x23, 0x00, 0x1A, 0x01, 0x10, 0x00, 0x41, 0x60},  // statusword
      {0x23, 0x00, 0x1A, 0x02, 0x10, 0x00, 0x3F, 0x60},  // error code
      {0x23, 0x00, 0x1A, 0x03, 0x20, 0x00, 0x6C, 0x60},  // velocity actual
      {0x2F, 0x00, 0x1A, 0x00, 0x03, 0, 0, 0},           // count 3
      {0x2F, 0x00, 0x18, 0x02, 0x01, 0, 0, 0},           // synchronous
      {0x23, 0x00, 0x18, 0x01, 0x83, 0x01, 0x00, 0x00},  // TPDO1 valid
  };
  ASSERT_EQ(requests.size(), 51U);  // 3 + 4 TPDOs (5 + entries each) + 2 RPDOs + 2 RPDOs off + 4 uploads
  EXPECT_EQ(std::vector<Bytes>(requests.begin(), requests.begin() + 11), expected);
  // TPDO4 and the RPDOs (the last of the mapping blocks) and what follows.
  const std::vector<Bytes> tail = {
      {0x23, 0x01, 0x14, 0x01, 0x03, 0x03, 0x00, 0x80},  // RPDO2 invalid
      {0x2F, 0x01, 0x16, 0x00, 0x00, 0, 0, 0},
      {0x23, 0x01, 0x16, 0x01, 0x10, 0x00, 0x40, 0x60},  // controlword
      {0x23, 0x01, 0x16, 0x02, 0x10, 0x00, 0x03, 0x20},  // phase set-point
      {0x2F, 0x01, 0x16, 0x00, 0x02, 0, 0, 0},
      {0x2F, 0x01, 0x14, 0x02, 0xFF, 0, 0, 0},  // event-driven
      {0x23, 0x01, 0x14, 0x01, 0x03, 0x03, 0x00, 0x00},
      {0x23, 0x02, 0x14, 0x01, 0x03, 0x04, 0x00, 0x80},  // RPDO3 off
      {0x23, 0x03, 0x14, 0x01, 0x03, 0x05, 0x00, 0x80},  // RPDO4 off
      {0x40, 0x40, 0x60, 0x00, 0, 0, 0, 0},              // what the drive holds: controlword, set-points
      {0x40, 0x01, 0x20, 0x00, 0, 0, 0, 0},
      {0x40, 0x02, 0x20, 0x00, 0, 0, 0, 0},
      {0x40, 0x03, 0x20, 0x00, 0, 0, 0, 0},
  };
  EXPECT_EQ(std::vector<Bytes>(requests.end() - static_cast<std::ptrdiff_t>(tail.size()), requests.end()), tail);
  // Then NMT start, one SYNC, and its four TPDOs with the mapped lengths.
  std::size_t start = boot;
  while (start < all.size() && !(all[start].id == 0x000 && bytes_of(all[start]) == Bytes{0x01, kNode})) ++start;
  ASSERT_LT(start, all.size());
  const std::vector<protocol::CanFrame> after(all.begin() + static_cast<std::ptrdiff_t>(start) + 1, all.end());
  ASSERT_EQ(with_id(after, 0x080).size(), 1U);
  EXPECT_EQ(with_id(after, 0x080)[0].dlc, 0);
  EXPECT_EQ(with_id(after, 0x183).at(0).dlc, 8);
  EXPECT_EQ(with_id(after, 0x283).at(0).dlc, 8);
  EXPECT_EQ(with_id(after, 0x383).at(0).dlc, 6);
  EXPECT_EQ(with_id(after, 0x483).at(0).dlc, 4);
  EXPECT_EQ(emu.request().mode, -1);
  EXPECT_TRUE(device->lockstep());
  EXPECT_EQ(device->name(), "canopen host node 3");
}

TEST(CanopenDevice, EnableWalksTheStateMachineOneCheckedTransitionPerCycle) {
  Emulator emu(true);
  const auto device = open(emu);
  (void)frames(*emu.spy);
  const DriveSetpoint s{40400.0, 0.0, 90.0, 0.0};
  DeviceTelemetry t;
  int cycles = 0;
  for (; cycles < 20 && !t.is(protocol::AmpState::enabled); ++cycles)
    t = device->step(s, {}, DeviceAction::enable, kSyncTicks);
  // The opening SYNC sampled the drive before its first tick (not ready to switch on: wait, 0x00);
  // then each controlword acts in the cycle its SYNC starts and shows at the next SYNC: sent twice.
  EXPECT_EQ(controlwords(frames(*emu.spy)), (std::vector<std::uint16_t>{0x00, 0x06, 0x06, 0x07, 0x07, 0x0F, 0x0F}));
  EXPECT_EQ(cycles, 7);
  EXPECT_EQ(emu.request().controlword, 0x0F);
  // Disable: disable operation, then shutdown, at rest in ready to switch on.
  for (cycles = 0; cycles < 20 && !t.is(protocol::AmpState::disabled); ++cycles)
    t = device->step(s, {}, DeviceAction::disable, kSyncTicks);
  for (int i = 0; i < 3; ++i) t = device->step(s, {}, DeviceAction::keep_alive, kSyncTicks);
  // Switched on already counts as disabled (the drive function is off); the walk goes on to rest.
  EXPECT_EQ(controlwords(frames(*emu.spy)), (std::vector<std::uint16_t>{0x07, 0x07, 0x06, 0x06, 0x06}));
  EXPECT_EQ(emu.after(device->syncs_sent() * kSyncTicks).cia402.statusword & 0x6F, 0x21);  // ready to switch on
}

TEST(CanopenDevice, LockstepStepsRunWholeSyncCyclesAndTheTelemetryIsTheCores) {
  Emulator emu(true);
  const auto device = open(emu);
  DriveSetpoint s{40200.0, 120.0, 90.0, 0.0};
  const DriveSlew slew{0.0, 2000.0};
  DeviceTelemetry t = step_until(*device, s, DeviceAction::enable, protocol::AmpState::enabled, 20, slew);
  ASSERT_TRUE(t.is(protocol::AmpState::enabled));
  // 0.2 s at 120 V (the 2000 V/s slew reaches it in 60 ms), four cycles per step.
  for (int i = 0; i < 50; ++i) t = device->step(s, slew, DeviceAction::keep_alive, 4 * kSyncTicks);
  const std::uint64_t ticks = device->syncs_sent() * kSyncTicks;
  const emu::Telemetry core = emu.after(ticks);
  EXPECT_EQ(core.tick, ticks) << "exactly the ticks of the SYNCs sent";
  // The next SYNC samples the state the core has now, in the bus's units.
  t = device->step(s, slew, DeviceAction::keep_alive, kSyncTicks);
  ASSERT_TRUE(t.device_time_s && t.tick);
  EXPECT_EQ(*t.tick, ticks);
  EXPECT_DOUBLE_EQ(*t.device_time_s, ticks / 10000.0);
  EXPECT_NEAR(t.speed_mm_s, core.speed_m_s * 1e3, 0.0006);
  EXPECT_NEAR(t.position_mm, core.position_m * 1e3, 0.0006);
  EXPECT_NEAR(t.frequency_hz, 40200.0, 1e-9);
  EXPECT_NEAR(t.amplitude_v, 120.0, 1e-9);
  EXPECT_NEAR(t.phase_deg, 90.0, 1e-9);
  ASSERT_TRUE(t.stator_temperature_c);
  EXPECT_NEAR(*t.stator_temperature_c, core.stator_temperature_c, 0.006);
  EXPECT_GT(t.speed_mm_s, 50.0) << "the motor runs at 120 V, 40.2 kHz";
  EXPECT_TRUE(t.drive_on);
  // The slews went by SDO in the drive's units (V/s of terminal amplitude).
  EXPECT_EQ(emu.request().amplitude_slew_v_per_s, 2000U);
  EXPECT_EQ(emu.request().frequency_slew_hz_per_s, 0U);
  EXPECT_EQ(emu.request().amplitude_mv, 120000U);
  EXPECT_EQ(emu.request().frequency_mhz, 40200000U);
}

TEST(CanopenDevice, TheDeviceSweepMeasuresTheModelsSteadySpeedInLockstep) {
  // `swum sweep`'s procedure (device_sweep.h) in lockstep: each read is one SYNC cycle, settle
  // and dwell on the device time the host counts. Each point is compared with the model's own
  // run to steady state (what the Modbus path is held to in tests/host/live_device_integration.py).
  Emulator emu(true);
  const auto device = open(emu);
  DeviceSweepPlan plan;
  plan.voltages = {150.0};
  plan.frequencies_hz = {40300.0, 40500.0};
  plan.settle_s = 0.06;
  plan.dwell_s = 0.03;
  plan.poll_interval_s = 0.0;
  std::vector<SweepRow> rows;
  sweep_device(*device, plan, rows);
  ASSERT_EQ(rows.size(), 2U);
  for (const SweepRow& row : rows) {
    ASSERT_TRUE(row.ok) << row.status;
    OperatingPoint point;
    point.amplitude_v = row.amplitude_v;
    point.frequency_hz = row.frequency_hz;
    const SteadyStateResult model = run_to_steady_state(emu::test::li2019_model(), point);
    ASSERT_TRUE(model.ok) << model.failure;
    EXPECT_NEAR(row.speed_mm_s, model.speed_mm_s, std::max(2.0, 0.03 * model.speed_mm_s)) << row.frequency_hz;
    EXPECT_TRUE(row.stator_temperature_c);
    EXPECT_FALSE(row.electrical);
  }
  EXPECT_EQ(rows[0].frequency_hz, 40500.0) << "swept downward";
  EXPECT_LT(rows[0].speed_mm_s, rows[1].speed_mm_s) << "nearer the resonance, faster";
  EXPECT_EQ(emu.request().controlword, 0x06) << "the sweep ends with the drive off, at rest in ready to switch on";
}

SpeedControlResult control_run(std::vector<SpeedControlRow>& rows) {
  Emulator emu(true);
  const auto device = open(emu);
  SpeedControlSettings s;
  s.target_mm_s = 300.0;
  s.frequency_hz = 40000.0;
  s.duration_s = 0.3;
  s.gains.kp_v_per_mm_s = kDefaultKpVPerMmS;
  s.gains.ki_v_per_mm = kDefaultKiVPerMm;
  SpeedControlHooks hooks;
  hooks.on_row = [&rows](const SpeedControlRow& row) { rows.push_back(row); };
  return run_speed_control(*device, s, hooks);
}

TEST(CanopenDevice, SwumControlHoldsItsTargetInLockstepAndRepeatsItself) {
  std::vector<SpeedControlRow> first, second;
  const SpeedControlResult a = control_run(first);
  const SpeedControlResult b = control_run(second);
  EXPECT_TRUE(a.stop_reason.empty()) << a.stop_reason;
  EXPECT_EQ(a.cycles, 300U);
  EXPECT_LT(a.mean_abs_error_last_half_mm_s, 0.05 * 300.0);
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(format_speed_control_row(first[i]), format_speed_control_row(second[i])) << "cycle " << i;
    if (HasFailure()) break;
  }
  EXPECT_EQ(a.mean_abs_error_last_half_mm_s, b.mean_abs_error_last_half_mm_s);
  // The opening SYNC and swum control's first read ran a cycle each; then one per control cycle.
  EXPECT_EQ(*first.back().tick, 10U * 301U);
}

TEST(CanopenDevice, StepsThatAreNoWholeSyncCyclesAreRefused) {
  Emulator emu(true);
  const auto device = open(emu);
  try {
    (void)device->step({}, {}, DeviceAction::keep_alive, 15);
    FAIL() << "15 ticks is 1.5 SYNC cycles";
  } catch (const DeviceError& e) {
    EXPECT_STREQ(e.what(),
                 "canopen host node 3: a step of 15 ticks is not a whole number of the node's 10-tick SYNC cycles "
                 "(--sync-ticks; the control cycle --cycle-ms x --tick-hz / 1000 must be a multiple of it)");
  }
  EXPECT_THROW((void)device->step({}, {}, DeviceAction::keep_alive, 0), DeviceError);
}

// The set-point's amplitude is 0x2002's terminal amplitude one to one: 100 V is 100000 mV.
TEST(CanopenDevice, TheAmplitudeIsTheTerminalAmplitudeOneToOne) {
  Emulator emu(true);
  const auto device = open(emu);
  (void)frames(*emu.spy);
  device->set_drive({40300.0, 100.0, -90.0, 0.0});
  const auto rpdo1 = with_id(frames(*emu.spy), 0x200 + kNode);
  ASSERT_EQ(rpdo1.size(), 1U);
  EXPECT_EQ(bytes_of(rpdo1[0]), (Bytes{0xE0, 0xED, 0x66, 0x02, 0xA0, 0x86, 0x01, 0x00}));  // 40300000 mHz, 100000 mV
  (void)device->read();
  EXPECT_EQ(emu.request().amplitude_mv, 100000U);
  EXPECT_EQ(emu.request().phase_cdeg, -9000);
}

TEST(CanopenDevice, AFaultShowsWithItsSwumCodeAndAResetEdgeClearsIt) {
  Emulator emu(true, emu::test::scenario_of({"over_temperature@0.05"}));
  const auto device = open(emu);
  const DriveSetpoint s{40400.0, 80.0, 90.0, 0.0};
  DeviceTelemetry t = step_until(*device, s, DeviceAction::enable, protocol::AmpState::fault, 200);
  ASSERT_TRUE(t.is(protocol::AmpState::fault));
  EXPECT_EQ(t.fault_code, static_cast<int>(protocol::FaultCode::over_temperature)) << "0x603F 0x4310";
  EXPECT_FALSE(t.drive_on);
  (void)frames(*emu.spy);
  t = step_until(*device, {s.frequency_hz, 0.0, 90.0, 0.0}, DeviceAction::reset_fault, protocol::AmpState::disabled,
                 20);
  EXPECT_TRUE(t.is(protocol::AmpState::disabled));
  EXPECT_EQ(t.fault_code, 0);
  // One rising edge of bit 7, then shutdown towards rest.
  const std::vector<std::uint16_t> words = controlwords(frames(*emu.spy));
  const auto edge = std::find(words.begin(), words.end(), 0x80);
  ASSERT_NE(edge, words.end());
  EXPECT_EQ(std::count(words.begin(), words.end(), 0x80), 1);
  EXPECT_EQ(emu.request().fault_reset_edges, 1U);
}

TEST(CanopenDevice, OnTheWallClockAReadIsOneSyncAndCommandsWalkToTheirState) {
  Emulator emu(false);
  const auto device = open(emu, CanopenNode{});
  EXPECT_FALSE(device->lockstep());
  (void)frames(*emu.spy);
  const std::uint64_t syncs = device->syncs_sent();
  DeviceTelemetry t = device->read();
  EXPECT_FALSE(t.device_time_s);
  EXPECT_FALSE(t.tick);
  EXPECT_EQ(device->syncs_sent(), syncs + 1);
  EXPECT_EQ(with_id(frames(*emu.spy), 0x080).size(), 1U);
  device->set_drive({40400.0, 0.0, 90.0, 0.0});
  device->command(DeviceAction::enable);
  EXPECT_EQ(device->read().state, static_cast<int>(protocol::AmpState::enabled));
  const std::vector<std::uint16_t> words = controlwords(frames(*emu.spy));
  ASSERT_GE(words.size(), 3U);
  // set_drive repeats the drive's controlword (0 after boot), then the walk: 0x06, 0x07, 0x0F.
  std::vector<std::uint16_t> distinct;
  for (const std::uint16_t w : words)
    if (distinct.empty() || distinct.back() != w) distinct.push_back(w);
  EXPECT_EQ(distinct, (std::vector<std::uint16_t>{0x00, 0x06, 0x07, 0x0F}));
  device->command(DeviceAction::disable);
  EXPECT_EQ(device->read().state, static_cast<int>(protocol::AmpState::disabled));
  EXPECT_EQ(device->controlword(), 0x06);
  EXPECT_THROW((void)device->step({}, {}, DeviceAction::keep_alive, kSyncTicks), DeviceError) << "not in lockstep";
}

TEST(CanopenDevice, ASecondMasterReadsTheDriveBackAndLeavesItRunning) {
  Emulator emu(true);
  const auto first = open(emu);
  const DriveSetpoint s{40500.0, 30.0, 80.0, 0.0};
  DeviceTelemetry t = step_until(*first, s, DeviceAction::enable, protocol::AmpState::enabled, 20);
  ASSERT_TRUE(t.is(protocol::AmpState::enabled));
  // `swum log` opens the node again: reset communication, remapping, but no controlword of its own.
  const auto second = open(emu);
  EXPECT_EQ(second->controlword(), 0x0F);
  for (int i = 0; i < 3; ++i) t = second->read();
  EXPECT_TRUE(t.is(protocol::AmpState::enabled));
  EXPECT_NEAR(t.frequency_hz, 40500.0, 1e-9);
  EXPECT_NEAR(t.phase_deg, 80.0, 1e-9);
  EXPECT_EQ(emu.request().amplitude_mv, 30000U);
}

TEST(CanopenDevice, ASecondMastersOpeningLeavesAFaultAlone) {
  // A fault reset edge counted before (the first fault, reset), then a second fault: opening the
  // node again (NMT reset communication) must not count as another edge.
  Emulator emu(true, emu::test::scenario_of(
                         {"over_temperature@0.02", "clear@0.04:fault=over_temperature", "over_temperature@0.08"}));
  const auto first = open(emu);
  const DriveSetpoint s{40400.0, 50.0, 90.0, 0.0};
  DeviceTelemetry t = step_until(*first, s, DeviceAction::enable, protocol::AmpState::fault, 100);
  ASSERT_TRUE(t.is(protocol::AmpState::fault));
  t = step_until(*first, s, DeviceAction::reset_fault, protocol::AmpState::disabled, 100);
  t = step_until(*first, s, DeviceAction::enable, protocol::AmpState::fault, 100);
  ASSERT_TRUE(t.is(protocol::AmpState::fault));
  ASSERT_EQ(emu.request().fault_reset_edges, 1U);
  const auto second = open(emu);
  for (int i = 0; i < 3; ++i) t = second->read();
  EXPECT_TRUE(t.is(protocol::AmpState::fault)) << "a reset communication is no fault reset";
}

TEST(CanopenDevice, ALoadAndSetpointsTheObjectsCannotHoldAreRefused) {
  Emulator emu(true);
  const auto device = open(emu);
  try {
    device->set_drive({40400.0, 10.0, 90.0, 1.5});
    FAIL();
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("the CiA 402 drive has no load input"), std::string::npos) << e.what();
  }
  try {
    device->set_drive({40400.0, 10.0, 200.0, 0.0});
    FAIL();
  } catch (const DeviceError& e) {
    EXPECT_STREQ(e.what(),
                 "canopen host node 3: phase_deg 200 is outside what the CiA 402 drive takes (0x2003: -180..180 deg)");
  }
  // A frequency outside the amplifier's limits is refused by the drive's SDO check (slews and
  // set-points at opening), not by the RPDO, which CiA 301 does not acknowledge.
  EXPECT_THROW(device->set_slew(-1.0, 0.0), DeviceError);
}

TEST(CanopenDevice, ARebootOfTheNodeIsReported) {
  Emulator emu(true);
  const auto device = open(emu);
  protocol::CanFrame reset;
  reset.id = 0x000;
  reset.dlc = 2;
  reset.data[0] = 0x81;  // NMT reset node, from another master
  reset.data[1] = kNode;
  ASSERT_TRUE(emu.spy->send(reset).ok());
  try {
    for (int i = 0; i < 5; ++i) (void)device->read();
    FAIL() << "the reboot went unnoticed";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("rebooted"), std::string::npos) << e.what();
  }
}

TEST(CanopenDevice, NoNodeNoAnswer) {
  auto network = io::FakeCanNetwork::create();
  try {
    CanopenDevice device(network->attach("vcan9"), kNode, {},
                         {std::chrono::milliseconds(100), std::chrono::milliseconds(100)});
    FAIL();
  } catch (const DeviceError& e) {
    EXPECT_STREQ(e.what(),
                 "canopen vcan9 node 3: no answer to an SDO read of the device type within 100 ms (is swum-emu "
                 "running with --can vcan9 --node 3 --can-profile cia402?)");
  }
}

// A node that boots and serves SDO from a dictionary the test changes (another device profile).
class StandIn {
 public:
  explicit StandIn(std::shared_ptr<io::FakeCanNetwork> network) : bus_(network->attach("standin")) {
    thread_ = std::thread([this] {
      while (!stop_) {
        io::CanFrame f;
        if (!bus_->receive(f, std::chrono::milliseconds(5)).ok()) continue;
        protocol::CanFrame answer;
        if (f.id == 0x000 && f.dlc == 2 && f.data[0] == 0x82 && f.data[1] == kNode) {
          answer.id = 0x700 + kNode;
          answer.dlc = 1;
          (void)bus_->send(answer);
        } else if (sdo_.receive(f, 0, answer)) {
          (void)bus_->send(answer);
        }
      }
    });
  }
  ~StandIn() {
    stop_ = true;
    thread_.join();
  }
  canopen::ObjectDictionary od{canopen::swum_eds_objects(), kNode};

 private:
  std::unique_ptr<io::FakeCanBus> bus_;
  canopen::SdoServer sdo_{od, kNode};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

std::string open_error(std::shared_ptr<io::FakeCanNetwork> network) {
  try {
    CanopenDevice device(network->attach("host"), kNode, {}, kTimeouts);
  } catch (const DeviceError& e) {
    return e.what();
  }
  return "opened";
}

TEST(CanopenDevice, RefusesANodeThatIsNoCia402DriveWithModeMinusOne) {
  auto network = io::FakeCanNetwork::create();
  {
    StandIn node(network);
    node.od.set(node.od.slot(0x1000, 0), 0x00020191);  // CiA 401: I/O modules
    EXPECT_EQ(open_error(network),
              "canopen host node 3: not a CiA 402 drive (device type 0x1000 = 0x00020191, profile 401)");
  }
  {
    StandIn node(network);
    node.od.set(node.od.slot(0x6502, 0), 0x00000004);  // profile velocity only
    EXPECT_EQ(open_error(network),
              "canopen host node 3: the drive does not offer the open-loop mode -1 (supported drive modes 0x6502 = "
              "0x00000004, bit 16 clear)");
  }
}

TEST(CanopenDeviceAddress, IsIfaceColonNode) {
  std::string interface;
  EXPECT_EQ(parse_canopen_address("vcan0:3", interface), 3);
  EXPECT_EQ(interface, "vcan0");
  EXPECT_EQ(parse_canopen_address("can1:127", interface), 127);
  const std::pair<const char*, const char*> bad[] = {
      {"vcan0", "--canopen: expected IFACE:NODE (node 1..127), got 'vcan0'"},
      {":3", "--canopen: expected IFACE:NODE (node 1..127), got ':3'"},
      {"vcan0:", "--canopen: node must be an integer 1..127, got ''"},
      {"vcan0:0", "--canopen: node must be an integer 1..127, got '0'"},
      {"vcan0:128", "--canopen: node must be an integer 1..127, got '128'"},
      {"vcan0:3x", "--canopen: node must be an integer 1..127, got '3x'"},
  };
  for (const auto& [text, message] : bad) {
    try {
      (void)parse_canopen_address(text, interface);
      ADD_FAILURE() << text;
    } catch (const std::invalid_argument& e) {
      EXPECT_STREQ(e.what(), message);
    }
  }
}

}  // namespace
}  // namespace swum::host
