// Cost of one harmonic-balance point of the free stator (issue target: <= 20 us). Reported:
// both modes, every branch (closed-form seeds + AFT Newton + stability + sensitivities), at a
// single-valued point and at a three-branch point; and one mode from one seed.
#include <benchmark/benchmark.h>

#include "analysis/free_stator/harmonic_balance.h"
#include "model/motor_model.h"

namespace {

const swum::MotorModel& model() {
  static const swum::MotorModel m{swum::MotorParameters{}};
  return m;
}

void BM_HarmonicBalancePoint_BothModes_400V_39k5Hz(benchmark::State& state) {
  const swum::FreeStatorHarmonicBalance hb(model());
  for (auto _ : state) {
    auto r = hb.solve(400.0, 39500.0);
    benchmark::DoNotOptimize(r);
  }
}

void BM_HarmonicBalancePoint_BothModes_ThreeBranches_400V_39kHz(benchmark::State& state) {
  const swum::FreeStatorHarmonicBalance hb(model());
  for (auto _ : state) {
    auto r = hb.solve(400.0, 39000.0);
    benchmark::DoNotOptimize(r);
  }
}

void BM_HarmonicBalance_OneModeOneSeed(benchmark::State& state) {
  const swum::FreeStatorHarmonicBalance hb(model());
  const auto seed = hb.closed_form_seeds(swum::StatorMode::b2, 400.0, 39500.0).front();
  swum::ModeBranch branch;
  for (auto _ : state) {
    benchmark::DoNotOptimize(hb.polish(swum::StatorMode::b2, 400.0, 39500.0, seed, branch));
  }
}

void BM_HarmonicBalance_Backbone_400V(benchmark::State& state) {
  const swum::FreeStatorHarmonicBalance hb(model());
  for (auto _ : state) {
    auto b = hb.backbone(400.0);
    benchmark::DoNotOptimize(b);
  }
}

}  // namespace

BENCHMARK(BM_HarmonicBalancePoint_BothModes_400V_39k5Hz)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_HarmonicBalancePoint_BothModes_ThreeBranches_400V_39kHz)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_HarmonicBalance_OneModeOneSeed)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_HarmonicBalance_Backbone_400V)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
