#include "analysis/studies/population.h"

#include <Random123/philox.h>
#include <Random123/boxmuller.hpp>
#include <Random123/uniform.hpp>

#include <algorithm>
#include <cmath>
#include <queue>
#include <stdexcept>

namespace swum {
namespace {

// The second key word: a study seed shared with another use of Philox elsewhere would
// still give other numbers here.
constexpr std::uint64_t kPopulationKey = 0x53574d504f50ull;  // "SWMPOP"
// Far beyond what a truncation of >= 0.5 sigma needs (P(fail) < 0.62^1000); reaching it
// would mean a broken generator.
constexpr std::uint64_t kMaxAttempts = 1000;

double draw_one(const ParameterSpread& s, std::uint64_t seed, std::uint64_t motor) {
  r123::Philox4x64 philox;
  const r123::Philox4x64::key_type key = {{seed, kPopulationKey}};
  for (std::uint64_t attempt = 0; attempt < kMaxAttempts; ++attempt) {
    const r123::Philox4x64::ctr_type counter = {{motor, s.stream, attempt, 0}};
    const auto r = philox(counter, key);
    if (s.distribution == SpreadDistribution::uniform) {
      const double u = r123::u01<double>(r.v[0]);  // (0, 1]
      return std::clamp(s.low + (s.high - s.low) * u, s.low, s.high);
    }
    const double z = r123::boxmuller(r.v[0], r.v[1]).x;
    if (std::abs(z) <= s.truncate) return s.nominal + s.sigma * z;
  }
  throw std::logic_error("population draw: no normal value within the truncation in 1000 attempts");
}

double quantile(const std::vector<double>& sorted, double p) {
  const double h = p * static_cast<double>(sorted.size() - 1);
  const auto i = static_cast<std::size_t>(std::floor(h));
  if (i + 1 >= sorted.size()) return sorted.back();
  return sorted[i] + (h - static_cast<double>(i)) * (sorted[i + 1] - sorted[i]);
}

}  // namespace

std::vector<double> draw_spread_values(const std::vector<ParameterSpread>& spreads, std::uint64_t seed,
                                       std::uint64_t motor) {
  std::vector<double> values;
  values.reserve(spreads.size());
  for (const ParameterSpread& s : spreads) values.push_back(draw_one(s, seed, motor));
  return values;
}

MotorParameters with_drawn_values(MotorParameters nominal, const std::vector<ParameterSpread>& spreads,
                                  const std::vector<double>& values) {
  for (std::size_t k = 0; k < spreads.size() && k < values.size(); ++k) spreads[k].spec->set(nominal, values[k]);
  return nominal;
}

Distribution describe_distribution(std::vector<double> values) {
  Distribution d;
  d.count = values.size();
  if (values.empty()) return d;
  std::sort(values.begin(), values.end());
  d.min = values.front();
  d.p5 = quantile(values, 0.05);
  d.p50 = quantile(values, 0.50);
  d.p95 = quantile(values, 0.95);
  d.max = values.back();
  return d;
}

FrequencyBand narrowest_band(const std::vector<std::optional<std::pair<double, double>>>& spans, double yield) {
  FrequencyBand band;
  band.needed = static_cast<std::size_t>(std::ceil(yield * static_cast<double>(spans.size()) - 1e-9));
  band.needed = std::max<std::size_t>(band.needed, 1);
  std::vector<std::pair<double, double>> coverable;
  for (const auto& s : spans) {
    if (s) coverable.push_back(*s);
  }
  if (coverable.size() < band.needed) return band;
  // Lowest ends from the top down; the heap keeps the `needed` smallest upper ends among the
  // motors starting at or above the current low end: the narrowest interval starting there.
  std::sort(coverable.begin(), coverable.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::priority_queue<double> highs;
  double best = INFINITY;
  for (const auto& [low, high] : coverable) {
    highs.push(high);
    if (highs.size() > band.needed) highs.pop();
    if (highs.size() == band.needed && highs.top() - low <= best) {
      best = highs.top() - low;
      band.low_hz = low;
      band.high_hz = highs.top();
    }
  }
  band.reached = true;
  band.covered = static_cast<std::size_t>(std::count_if(coverable.begin(), coverable.end(), [&](const auto& s) {
    return s.first >= band.low_hz && s.second <= band.high_hz;
  }));
  return band;
}

}  // namespace swum
