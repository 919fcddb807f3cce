// Lockstep throughput (issue 13): emulated seconds per wall second when a controller steps
// swum-emu 1 ms (10 ticks at 10 kHz) per cycle, with the calibrated motor driven at 400 V,
// 40 kHz. Side by side in one run:
//   CoreTicks      EmulatorCore::tick() x 10 on the calling thread: the model's floor;
//   InProcess      LockstepClock::advance(10) to a LockstepLoop thread (the hand-off cost);
//   ModbusTcp      a libmodbus client on 127.0.0.1: one FC16 of holding 0..10 (command,
//                  set-points, slews, advance 10: the reply comes when the ticks are done) and
//                  one FC04 of the 36 input registers per cycle, against ModbusTcpServer.
// Counter x_real_time = emulated s per wall s (real time: the two threads' hand-offs count).
// Run: build/release/tests/benchmarks/bench_lockstep --benchmark_repetitions=3  (Release build).
#include <benchmark/benchmark.h>
#include <modbus.h>

#include <array>
#include <atomic>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "core/emulator_core.h"
#include "core/lockstep_clock.h"
#include "formats/parameter_file.h"
#include "modbus_codec.h"
#include "test_paths.h"
#include "transports/modbus_server.h"

namespace {

using namespace swum;
using namespace swum::emu;
constexpr std::uint32_t kTicksPerCycle = 10;  // 1 ms at 10 kHz

const MotorModel& model() {
  static const MotorModel m = [] {
    std::ifstream in(swum::test::source_path("config/li2019.toml"));
    std::stringstream text;
    text << in.rdbuf();
    return MotorModel(parse_motor_parameters(text.str(), "li2019.toml"));
  }();
  return m;
}

Command drive_400v() {
  Command c;
  c.fields = Command::kAction | Command::kAmplitude | Command::kFrequency;
  c.action = Action::enable;
  c.amplitude_v = 400.0;
  c.frequency_hz = 40000.0;
  return c;
}

void report(benchmark::State& state) {
  state.counters["x_real_time"] = benchmark::Counter(static_cast<double>(state.iterations()) * kTicksPerCycle * 1e-4,
                                                     benchmark::Counter::kIsRate);
}

void BM_Lockstep_CoreTicks(benchmark::State& state) {
  SharedState shared;
  EmulatorCore core(model(), {}, shared);
  shared.submit(drive_400v());
  for (auto _ : state) {
    for (std::uint32_t i = 0; i < kTicksPerCycle; ++i) benchmark::DoNotOptimize(core.tick());
  }
  report(state);
}

// The loop thread runs for the whole benchmark; every iteration is one step.
struct LockstepRig {
  SharedState shared;
  LockstepClock clock;
  EmulatorCore core;
  LockstepLoop loop;
  std::atomic<bool> stop{false};
  std::thread thread;
  LockstepRig() : core(model(), external(), shared), loop(core, clock, {}) {
    shared.lockstep = &clock;
    shared.submit(drive_400v());
    thread = std::thread([this] { loop.run(stop); });
  }
  ~LockstepRig() {
    stop = true;
    thread.join();
  }
  static CoreConfig external() {
    CoreConfig c;
    c.external_clock = true;
    return c;
  }
};

void BM_Lockstep_InProcess(benchmark::State& state) {
  LockstepRig rig;
  for (auto _ : state) {
    if (!rig.clock.advance(kTicksPerCycle)) state.SkipWithError("the loop stopped");
  }
  report(state);
}

void BM_Lockstep_ModbusTcp(benchmark::State& state) {
  LockstepRig rig;
  ModbusTcpServer server("127.0.0.1", 0, rig.shared, AmplifierLimits{});
  server.start();
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", server.port());
  if (ctx == nullptr || modbus_connect(ctx) != 0) {
    state.SkipWithError("cannot connect to the in-process server");
    if (ctx) modbus_free(ctx);
    server.stop();
    return;
  }
  namespace mb = protocol::modbus;
  AmplifierSetpoints s;
  s.frequency_hz = 40000.0;
  s.amplitude_v = 400.0;
  s.phase_deg = 90.0;
  std::array<std::uint16_t, mb::holding::kCount> step{};
  if (!mb::encode_step_write(Action::none, s, kTicksPerCycle, step).empty()) state.SkipWithError("encode");
  std::array<std::uint16_t, mb::input::kCount> input{};
  for (auto _ : state) {
    if (modbus_write_registers(ctx, 0, mb::holding::kCount, step.data()) != mb::holding::kCount ||
        modbus_read_input_registers(ctx, 0, mb::input::kCount, input.data()) != mb::input::kCount) {
      state.SkipWithError(modbus_strerror(errno));
      break;
    }
  }
  report(state);
  modbus_close(ctx);
  modbus_free(ctx);
  server.stop();
}

BENCHMARK(BM_Lockstep_CoreTicks)->UseRealTime()->MinTime(1.0);
BENCHMARK(BM_Lockstep_InProcess)->UseRealTime()->MinTime(1.0);
BENCHMARK(BM_Lockstep_ModbusTcp)->UseRealTime()->MinTime(1.0);

}  // namespace

BENCHMARK_MAIN();
