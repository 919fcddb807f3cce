#include "analysis/identification/identification.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "analysis/free_stator/synthetic_amplitudes.h"
#include "model/motor_model.h"

namespace swum {
namespace {

// 10 voltages x 3 frequencies = 30 points (60 amplitudes), model_spec §6.5 / paper Figs. 7-8:
// the paper's 50..365 Vpp, read as the library defaults read them (peak-to-peak, model_spec §0),
// are these terminal amplitudes.
const std::vector<double> kVoltages = {25, 42.5, 60, 77.5, 95, 112.5, 130, 147.5, 165, 182.5};
const std::vector<double> kFrequencies = {39250.0, 39500.0, 39750.0};

MotorParameters truth() { return MotorParameters{}; }  // Table 2 (library defaults)

// A prior away from the truth: every non-linear constant off by a factor.
MotorParameters offset_prior() {
  MotorParameters p{};
  p.stator.c111_pa *= 1.8;
  p.stator.c1111_pa *= 0.5;
  p.stator.e311_c_per_v_m *= 0.4;
  p.stator.e3111_c_per_v_m *= 2.0;
  return p;
}

void print(const IdentificationResult& r) {
  for (const auto& e : r.parameters) {
    std::printf("  %-16s prior %+.4e  value %+.4e  se %.3e  %s%s\n", std::string(e.key).c_str(), e.prior, e.value,
                e.standard_error, e.identifiable ? "identified" : "NOT identifiable",
                e.significant ? " (significant)" : "");
  }
  std::printf("  rms relative residual %.4f, starts %d, rounds %d\n", r.rms_relative_residual, r.starts_run, r.rounds);
}

TEST(Identification, RoundTripRecoversTheIdentifiableParameters) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    SyntheticAmplitudeOptions so;
    so.relative_noise = 0.02;
    so.seed = seed;
    const auto data = synthesize_amplitudes(truth(), kVoltages, kFrequencies, so);
    ASSERT_EQ(data.size(), 30u);
    const IdentificationResult r = identify_nonlinear_parameters(offset_prior(), data);
    ASSERT_TRUE(r.ok) << r.failure;
    print(r);
    const StatorParameters t = truth().stator;
    int identified = 0;
    for (const auto& e : r.parameters) {
      const double true_value = nonlinear_parameter_value(t, e.parameter);
      if (e.identifiable) {
        ++identified;
        EXPECT_LT(std::abs(e.value - true_value), 2.0 * e.standard_error) << e.key << " seed " << seed;
        EXPECT_LT(std::abs(e.value - true_value), 0.15 * std::abs(true_value)) << e.key;
        EXPECT_TRUE(std::isfinite(e.standard_error));
      } else {
        EXPECT_EQ(e.value, e.prior) << e.key;  // kept at the prior, never a made-up number
        EXPECT_FALSE(std::isfinite(e.standard_error));
        EXPECT_FALSE(e.reason.empty());
      }
    }
    EXPECT_TRUE(r.parameters[1].identifiable) << "c1111 is determined by such data (§6.5)";
    EXPECT_FALSE(r.parameters[0].identifiable) << "c111 only shifts the DC offset (§6.5)";
    EXPECT_FALSE(r.parameters[2].identifiable) << "e311 has no first-harmonic effect (§6.5)";
    EXPECT_GE(identified, 1);
    // The fitted curves lie within the noise: residual ~ the 2 % noise, and the fitted model
    // against the noise-free truth within the noise level.
    EXPECT_LT(r.rms_relative_residual, 0.025);
    // Pointwise on the branch nearest the noise-free truth (near a fold the followed branch
    // may differ between two parameter sets).
    const auto exact = synthesize_amplitudes(truth(), kVoltages, kFrequencies, {});
    const MotorModel model(truth());
    const FreeStatorHarmonicBalance hb(model.constants(), r.fitted_stator);
    double sum2 = 0.0;
    double worst = 0.0;
    int n = 0;
    for (const auto& x : exact) {
      const auto u = predicted_branch(hb, StatorMode::l1, x.amplitude_v, x.frequency_hz, x.tip_normal_um);
      const auto w = predicted_branch(hb, StatorMode::b2, x.amplitude_v, x.frequency_hz, x.tip_tangential_um);
      ASSERT_TRUE(u && w);
      for (double e :
           {u->tip_amplitude_um / *x.tip_normal_um - 1.0, w->tip_amplitude_um / *x.tip_tangential_um - 1.0}) {
        sum2 += e * e;
        worst = std::max(worst, std::abs(e));
        ++n;
      }
    }
    const double rms = std::sqrt(sum2 / n);
    std::printf("  fitted vs noise-free truth: rms %.4f, worst %.4f\n", rms, worst);
    // Within the 2 % noise on average; the worst point sits at the B2 peak (190 V, 39.25 kHz),
    // where dW/dc1111 is largest.
    EXPECT_LT(rms, 0.02);
    EXPECT_LT(worst, 0.06);
  }
}

TEST(Identification, LinearModelDataGiveNoSignificantNonlinearity) {
  SyntheticAmplitudeOptions so;
  so.relative_noise = 0.02;
  so.seed = 7;
  const auto data = synthesize_amplitudes(linearised(truth()), kVoltages, kFrequencies, so);
  const IdentificationResult r = identify_nonlinear_parameters(truth(), data);
  ASSERT_TRUE(r.ok) << r.failure;
  print(r);
  for (const auto& e : r.parameters) EXPECT_FALSE(e.significant) << e.key;
  EXPECT_TRUE(r.parameters[1].identifiable);  // c1111 = 0 +- se: determined, and zero
  EXPECT_LT(std::abs(r.parameters[1].value), 0.1 * std::abs(truth().stator.c1111_pa));
}

TEST(Identification, NoiseFreeDataAreFittedExactly) {
  const auto data = synthesize_amplitudes(truth(), kVoltages, kFrequencies, {});
  const IdentificationResult r = identify_nonlinear_parameters(offset_prior(), data);
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_LT(r.rms_relative_residual, 1e-4);  // c111, e311 stay at the (wrong) prior
  EXPECT_NEAR(r.parameters[1].value, truth().stator.c1111_pa, 1e-4 * std::abs(truth().stator.c1111_pa));
  EXPECT_FALSE(r.parameters[0].identifiable);  // flat direction, whatever the noise
}

TEST(Identification, TangentialOnlyDataStillDetermineC1111) {
  SyntheticAmplitudeOptions so;
  so.relative_noise = 0.02;
  so.normal = false;
  const auto data = synthesize_amplitudes(truth(), kVoltages, kFrequencies, so);
  const IdentificationResult r = identify_nonlinear_parameters(offset_prior(), data);
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_TRUE(r.parameters[1].identifiable);
  EXPECT_NEAR(r.parameters[1].value, truth().stator.c1111_pa, 0.15 * std::abs(truth().stator.c1111_pa));
  EXPECT_FALSE(r.parameters[0].identifiable);  // c111 is in the L1 equation only
}

TEST(Identification, TooFewAmplitudesIsAFailureNotAFit) {
  std::vector<AmplitudeMeasurement> data(3);
  for (auto& d : data) {
    d.amplitude_v = 100;
    d.frequency_hz = 39500;
    d.tip_normal_um = 1.0;
  }
  const IdentificationResult r = identify_nonlinear_parameters(truth(), data);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("at least 4"), std::string::npos);
}

TEST(SyntheticAmplitudes, SameSeedSameData) {
  SyntheticAmplitudeOptions so;
  so.relative_noise = 0.02;
  so.seed = 11;
  const auto a = synthesize_amplitudes(truth(), kVoltages, kFrequencies, so);
  const auto b = synthesize_amplitudes(truth(), kVoltages, kFrequencies, so);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(*a[i].tip_normal_um, *b[i].tip_normal_um);
  so.seed = 12;
  const auto c = synthesize_amplitudes(truth(), kVoltages, kFrequencies, so);
  EXPECT_NE(*a[0].tip_normal_um, *c[0].tip_normal_um);
}

}  // namespace
}  // namespace swum
