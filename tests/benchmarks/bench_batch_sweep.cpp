// Operating points per second of a model sweep on one thread (issue 16: target >= 4x the scalar
// path per core): the same grid as the scalar loop of every sweep today (run_to_steady_state
// per point, from rest) and as batches in SIMD lanes (run_points_to_steady_state), side by side.
// Calibrated motor (config/li2019.toml), 4 voltages x 21 frequencies (39-41 kHz), default
// steady-state options; the same with a thermal effect and frozen temperature rises. Counter points_per_s = points /
// CPU second of this thread. Run: build/release/tests/benchmarks/bench_batch_sweep  (Release build).
#include <benchmark/benchmark.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/steady_state/steady_state_batch.h"
#include "formats/parameter_file.h"
#include "model/simulation/batch_simulator.h"
#include "test_paths.h"

namespace {

swum::MotorParameters calibrated() {
  std::ifstream in(swum::test::source_path("config/li2019.toml"));
  std::stringstream text;
  text << in.rdbuf();
  return swum::parse_motor_parameters(text.str(), "li2019.toml");
}

std::vector<swum::OperatingPoint> grid() {
  std::vector<swum::OperatingPoint> points;
  for (double amplitude_v : {100.0, 200.0, 300.0, 400.0}) {
    for (int k = 0; k <= 20; ++k) {
      swum::OperatingPoint p;
      p.amplitude_v = amplitude_v;
      p.frequency_hz = 39000.0 + 100.0 * k;
      points.push_back(p);
    }
  }
  return points;
}

void report(benchmark::State& state, std::size_t points) {
  state.counters["points_per_s"] = benchmark::Counter(static_cast<double>(points),
                                                      benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Sweep_Scalar(benchmark::State& state) {
  const swum::MotorModel model(calibrated());
  const std::vector<swum::OperatingPoint> points = grid();
  for (auto _ : state) {
    for (const swum::OperatingPoint& p : points) benchmark::DoNotOptimize(swum::run_to_steady_state(model, p));
  }
  report(state, points.size());
}

void BM_Sweep_Batch(benchmark::State& state) {
  const swum::MotorModel model(calibrated());
  const std::vector<swum::OperatingPoint> points = grid();
  const auto lanes = static_cast<std::size_t>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(swum::run_points_to_steady_state(model, points, {}, lanes));
  report(state, points.size());
  state.SetLabel(swum::BatchSimulator::simd_target());
}

// Predictions of measured points with a thermal effect: each point's temperature rise held
// fixed (per-lane model constants in the batch).
swum::MotorParameters thermal() {
  swum::MotorParameters p = calibrated();
  p.effects.thermal.enabled = true;
  p.effects.thermal.thermal_resistance_k_per_w = 5.0;
  return p;
}

std::vector<swum::OperatingPoint> frozen_grid() {
  std::vector<swum::OperatingPoint> points = grid();
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i].stator_temperature_rise_k = 0.5 * static_cast<double>(i % 20);
    points[i].freeze_slow_states = true;
  }
  return points;
}

void BM_SweepFrozenThermal_Scalar(benchmark::State& state) {
  const swum::MotorModel model(thermal());
  const std::vector<swum::OperatingPoint> points = frozen_grid();
  for (auto _ : state) {
    for (const swum::OperatingPoint& p : points) benchmark::DoNotOptimize(swum::run_to_steady_state(model, p));
  }
  report(state, points.size());
}

void BM_SweepFrozenThermal_Batch(benchmark::State& state) {
  const swum::MotorModel model(thermal());
  const std::vector<swum::OperatingPoint> points = frozen_grid();
  for (auto _ : state) benchmark::DoNotOptimize(swum::run_points_to_steady_state(model, points, {}, 16));
  report(state, points.size());
  state.SetLabel(swum::BatchSimulator::simd_target());
}

// The same batch (16 lanes) on each instruction set this CPU has (runtime dispatch restricted).
void BM_Sweep_Batch_Target(benchmark::State& state, const std::string& target) {
  if (!swum::BatchSimulator::restrict_simd_target(target)) {
    state.SkipWithError("target not available on this CPU");
    return;
  }
  const swum::MotorModel model(calibrated());
  const std::vector<swum::OperatingPoint> points = grid();
  for (auto _ : state) benchmark::DoNotOptimize(swum::run_points_to_steady_state(model, points, {}, 16));
  report(state, points.size());
  state.SetLabel(swum::BatchSimulator::simd_target());
  swum::BatchSimulator::restrict_simd_target("");
}

}  // namespace

BENCHMARK(BM_Sweep_Scalar)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Sweep_Batch)->Arg(8)->Arg(16)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SweepFrozenThermal_Scalar)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SweepFrozenThermal_Batch)->Unit(benchmark::kMillisecond);

int main(int argc, char** argv) {
  for (const std::string& target : swum::BatchSimulator::available_simd_targets()) {
    benchmark::RegisterBenchmark(("BM_Sweep_Batch_Target/" + target).c_str(), BM_Sweep_Batch_Target, target)
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
