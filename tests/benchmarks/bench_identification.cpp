// Identification of the four non-linear constants from 30 points (60 amplitudes, 2 % noise),
// default options (6 starts per fit, up to 4 fits). Issue target: <= 2 s on one core.
#include <benchmark/benchmark.h>

#include <vector>

#include "analysis/free_stator/synthetic_amplitudes.h"
#include "analysis/identification/identification.h"

namespace {

void BM_Identify4Parameters_30Points(benchmark::State& state) {
  const std::vector<double> amplitudes_v = {50, 85, 120, 155, 190, 225, 260, 295, 330, 365};
  const std::vector<double> freqs = {39250.0, 39500.0, 39750.0};
  swum::SyntheticAmplitudeOptions so;
  so.relative_noise = 0.02;
  const auto data = swum::synthesize_amplitudes(swum::MotorParameters{}, amplitudes_v, freqs, so);
  swum::MotorParameters prior{};
  prior.stator.c1111_pa *= 0.5;
  for (auto _ : state) {
    auto r = swum::identify_nonlinear_parameters(prior, data);
    benchmark::DoNotOptimize(r);
    state.counters["starts"] = r.starts_run;
  }
}

}  // namespace

BENCHMARK(BM_Identify4Parameters_30Points)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK_MAIN();
