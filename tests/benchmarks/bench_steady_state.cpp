// Cost of one operating point run to steady state (src/analysis/steady_state/steady_state.h), the unit of
// every sweep, pick, synth, fit and validation fact (issue 16, items 1 and 3). Side by side in
// one run:
//   StepByStep  the loop before issue 16: one step() call per step and the window statistics
//               added from state() and forces() after it (still the path when a trace is asked:
//               selected here with a trace that never fires);
//   HotLoop     the window statistics inside MotorSimulator::advance (the path now);
// each at 64 steps per 40 kHz period (the step before issue 16) and at the step of
// config/li2019.toml. Counters: ms_per_point (thread CPU, best iteration),
// real_time_factor = simulated s / CPU s for the whole point (settle + windows).
// Run: build/release/tests/benchmarks/bench_steady_state  (Release build).
#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "analysis/steady_state/steady_state.h"
#include "formats/parameter_file.h"
#include "test_paths.h"

namespace {

swum::MotorParameters calibrated(double steps_per_40khz_period) {
  std::ifstream in(swum::test::source_path("config/li2019.toml"));
  std::stringstream text;
  text << in.rdbuf();
  swum::MotorParameters p = swum::parse_motor_parameters(text.str(), "li2019.toml");
  if (steps_per_40khz_period > 0.0) p.numerics.time_step_ns = 1e9 / (40000.0 * steps_per_40khz_period);
  return p;
}

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// steps_per_period 0: the config's own step.
void run(benchmark::State& state, double steps_per_period, bool step_by_step, double amplitude_v, double frequency_hz) {
  const swum::MotorModel model(calibrated(steps_per_period));
  swum::SteadyStateOptions options;
  if (step_by_step) {
    options.trace = [](const swum::TraceSample&) {};
    options.trace_every_steps = std::numeric_limits<std::uint64_t>::max();
  }
  const swum::OperatingPoint point{amplitude_v, frequency_hz};
  double best_s = 1e30;
  double simulated_s = 0.0;
  for (auto _ : state) {
    const double t0 = thread_cpu_s();
    const swum::SteadyStateResult r = swum::run_to_steady_state(model, point, options);
    best_s = std::min(best_s, thread_cpu_s() - t0);
    simulated_s = r.sim_s;
    benchmark::DoNotOptimize(r.speed_mm_s);
  }
  state.counters["ms_per_point"] = 1e3 * best_s;
  state.counters["real_time_factor"] = simulated_s / best_s;
  state.counters["steps_per_period"] = 1.0 / (40000.0 * model.time_step_s());
}

void BM_Point400V40kHz_64Steps_StepByStep(benchmark::State& s) { run(s, 64.0, true, 400.0, 40000.0); }
void BM_Point400V40kHz_64Steps_HotLoop(benchmark::State& s) { run(s, 64.0, false, 400.0, 40000.0); }
void BM_Point400V40kHz_Config_HotLoop(benchmark::State& s) { run(s, 0.0, false, 400.0, 40000.0); }
void BM_Point100V40k3Hz_64Steps_StepByStep(benchmark::State& s) { run(s, 64.0, true, 100.0, 40300.0); }
void BM_Point100V40k3Hz_64Steps_HotLoop(benchmark::State& s) { run(s, 64.0, false, 100.0, 40300.0); }
void BM_Point100V40k3Hz_Config_HotLoop(benchmark::State& s) { run(s, 0.0, false, 100.0, 40300.0); }

BENCHMARK(BM_Point400V40kHz_64Steps_StepByStep)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Point400V40kHz_64Steps_HotLoop)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Point400V40kHz_Config_HotLoop)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Point100V40k3Hz_64Steps_StepByStep)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Point100V40k3Hz_64Steps_HotLoop)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Point100V40k3Hz_Config_HotLoop)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
