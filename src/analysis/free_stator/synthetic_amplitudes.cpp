#include "analysis/free_stator/synthetic_amplitudes.h"

#include <cmath>
#include <numbers>
#include <random>

#include "model/motor_model.h"

namespace swum {
namespace {

class GaussianSource {
 public:
  explicit GaussianSource(std::uint64_t seed) : rng_(seed) {}
  double next() {  // Box-Muller on 53-bit uniforms
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = 0.0;
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    const double radius = std::sqrt(-2.0 * std::log(u1));
    spare_ = radius * std::sin(2.0 * std::numbers::pi * u2);
    has_spare_ = true;
    return radius * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  double uniform() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }
  std::mt19937_64 rng_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace

std::vector<AmplitudeMeasurement> synthesize_amplitudes(const MotorParameters& parameters,
                                                        std::span<const double> amplitudes_v,
                                                        std::span<const double> frequencies_hz,
                                                        const SyntheticAmplitudeOptions& options) {
  const MotorModel model(parameters);
  const FreeStatorHarmonicBalance hb(model, options.harmonic_balance);
  GaussianSource noise(options.seed);
  std::vector<AmplitudeMeasurement> out;
  for (double f : frequencies_hz) {
    const std::vector<SweepPoint> sweep = sweep_voltage(hb, f, amplitudes_v);
    for (const SweepPoint& p : sweep) {
      if (p.followed_normal < 0 || p.followed_tangential < 0) continue;
      AmplitudeMeasurement m;
      m.amplitude_v = p.response.amplitude_v;
      m.frequency_hz = f;
      const double u = p.response.normal.branches[p.followed_normal].tip_amplitude_um;
      const double w = p.response.tangential.branches[p.followed_tangential].tip_amplitude_um;
      const double nu = noise.next();
      const double nw = noise.next();
      if (options.normal) m.tip_normal_um = u * (1.0 + options.relative_noise * nu);
      if (options.tangential) m.tip_tangential_um = w * (1.0 + options.relative_noise * nw);
      out.push_back(m);
    }
  }
  return out;
}

}  // namespace swum
