#include "analysis/fit/held_out_test.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <tuple>

namespace swum {

double signed_rank_p_value(std::span<const double> differences, double* w_plus) {
  std::vector<double> d;
  for (double x : differences) {
    if (x != 0.0 && std::isfinite(x)) d.push_back(x);
  }
  if (w_plus != nullptr) *w_plus = 0.0;
  const std::size_t m = d.size();
  if (m == 0) return 1.0;
  std::vector<std::size_t> order(m);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return std::abs(d[a]) < std::abs(d[b]); });
  // Doubled mid-ranks (whole numbers), so the exact distribution can be counted on integers.
  std::vector<int> rank2(m);
  double tie_correction = 0.0;  // sum of t^3 - t over tie groups
  for (std::size_t i = 0; i < m;) {
    std::size_t j = i;
    while (j + 1 < m && std::abs(d[order[j + 1]]) == std::abs(d[order[i]])) ++j;
    const int mid2 = static_cast<int>(i + j + 2);  // 2 x ((i+1 + j+1) / 2)
    for (std::size_t k = i; k <= j; ++k) rank2[order[k]] = mid2;
    const double t = static_cast<double>(j - i + 1);
    tie_correction += t * t * t - t;
    i = j + 1;
  }
  int w2 = 0;
  for (std::size_t i = 0; i < m; ++i) {
    if (d[i] > 0.0) w2 += rank2[i];
  }
  if (w_plus != nullptr) *w_plus = 0.5 * w2;
  const double md = static_cast<double>(m);
  if (m <= 300) {
    // P(W+ >= w) with each sign + or - with probability 1/2: distribution of the doubled sum.
    const int total = std::accumulate(rank2.begin(), rank2.end(), 0);
    std::vector<double> p(static_cast<std::size_t>(total) + 1, 0.0);
    p[0] = 1.0;
    int reach = 0;
    for (int r : rank2) {
      reach += r;
      for (int s = reach; s >= 0; --s) {
        const double with = s >= r ? p[static_cast<std::size_t>(s - r)] : 0.0;
        p[static_cast<std::size_t>(s)] = 0.5 * (p[static_cast<std::size_t>(s)] + with);
      }
    }
    double tail = 0.0;
    for (int s = w2; s <= total; ++s) tail += p[static_cast<std::size_t>(s)];
    return std::clamp(tail, 0.0, 1.0);
  }
  const double mean = md * (md + 1.0) / 4.0;
  const double var = md * (md + 1.0) * (2.0 * md + 1.0) / 24.0 - tie_correction / 48.0;
  if (var <= 0.0) return 1.0;
  const double z = (0.5 * w2 - 0.5 - mean) / std::sqrt(var);  // continuity correction
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

double sign_flip_p_value(std::span<const double> differences, std::uint64_t seed) {
  std::vector<double> d;
  for (double x : differences) {
    if (std::isfinite(x)) d.push_back(x);
  }
  const std::size_t m = d.size();
  if (m == 0) return 1.0;
  double observed = 0.0;
  for (double x : d) observed += x;
  // Ties with the observed sum count as at least as extreme (a tolerance for the rounding of
  // sums of these magnitudes).
  double magnitude = 0.0;
  for (double x : d) magnitude += std::abs(x);
  const double tolerance = 1e-12 * std::max(1.0, magnitude);
  std::uint64_t at_least = 0, total = 0;
  if (m <= 20) {
    const std::uint64_t patterns = std::uint64_t{1} << m;
    for (std::uint64_t bits = 0; bits < patterns; ++bits) {
      double sum = 0.0;
      for (std::size_t i = 0; i < m; ++i) sum += (bits >> i) & 1U ? -std::abs(d[i]) : std::abs(d[i]);
      if (sum >= observed - tolerance) ++at_least;
    }
    return static_cast<double>(at_least) / static_cast<double>(patterns);
  }
  std::mt19937_64 rng(seed);
  constexpr std::uint64_t kDraws = 200000;
  for (total = 0; total < kDraws; ++total) {
    double sum = 0.0;
    std::uint64_t bits = 0;
    for (std::size_t i = 0; i < m; ++i) {
      if (i % 64 == 0) bits = rng();
      sum += (bits >> (i % 64)) & 1U ? -std::abs(d[i]) : std::abs(d[i]);
    }
    if (sum >= observed - tolerance) ++at_least;
  }
  // The observed pattern counts as one of the draws: never p = 0 from a finite sample.
  return static_cast<double>(at_least + 1) / static_cast<double>(total + 1);
}

HeldOutEvidence compare_held_out(const MeasurementSet& set, const ResidualModel& model, std::span<const double> r0,
                                 std::span<const double> r1, std::span<const std::size_t> held_out_slots,
                                 std::uint64_t seed) {
  HeldOutEvidence e;
  // Per operating point: sums of squares of its values before and after, and their count.
  std::map<std::array<double, 3>, std::array<double, 3>> points;
  double ss0 = 0.0, ss1 = 0.0;
  for (std::size_t k : held_out_slots) {
    const Measurement& m = set.rows[model.slots()[k].row];
    auto& p = points[{m.amplitude_v, m.frequency_hz, m.load_n}];
    p[0] += r0[k] * r0[k];
    p[1] += r1[k] * r1[k];
    p[2] += 1.0;
    ss0 += r0[k] * r0[k];
    ss1 += r1[k] * r1[k];
  }
  if (held_out_slots.empty()) return e;
  const double n = static_cast<double>(held_out_slots.size());
  e.rms_before = std::sqrt(ss0 / n);
  e.rms_after = std::sqrt(ss1 / n);
  e.reduction = ss0 > 0.0 ? 1.0 - std::sqrt(ss1 / ss0) : 0.0;
  std::vector<double> differences, squared_differences;
  std::vector<std::array<double, 3>> sums;
  for (const auto& [key, p] : points) {
    const double before = std::sqrt(p[0] / p[2]);
    const double after = std::sqrt(p[1] / p[2]);
    differences.push_back(before - after);
    squared_differences.push_back((p[0] - p[1]) / p[2]);
    sums.push_back(p);
    ++e.points;
    if (after < before) ++e.improved;
    if (after == before) ++e.unchanged;
  }
  e.signed_rank_p = signed_rank_p_value(differences, &e.signed_rank);
  e.sign_flip_p = sign_flip_p_value(squared_differences, seed ^ 0x9E3779B97F4A7C15ULL);  // own stream
  e.p_value = std::min(1.0, 2.0 * std::min(e.signed_rank_p, e.sign_flip_p));
  // Percentile bootstrap of the reduction over operating points (2000 resamples).
  std::mt19937_64 rng(seed);
  constexpr int kResamples = 2000;
  std::vector<double> reductions;
  reductions.reserve(kResamples);
  const std::size_t count = sums.size();
  for (int b = 0; b < kResamples; ++b) {
    double a0 = 0.0, a1 = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
      const auto& p = sums[rng() % count];
      a0 += p[0];
      a1 += p[1];
    }
    reductions.push_back(a0 > 0.0 ? 1.0 - std::sqrt(a1 / a0) : 0.0);
  }
  std::sort(reductions.begin(), reductions.end());
  e.reduction_low = reductions[static_cast<std::size_t>(0.05 * (kResamples - 1))];
  e.reduction_high = reductions[static_cast<std::size_t>(0.95 * (kResamples - 1))];
  return e;
}

std::vector<bool> held_out_rows(const MeasurementSet& set, const HeldOutSplit& options, int& held_points,
                                int& point_count) {
  std::map<std::tuple<double, double, double>, std::size_t> group_of;
  std::vector<std::size_t> group(set.rows.size());
  for (std::size_t i = 0; i < set.rows.size(); ++i) {
    const Measurement& m = set.rows[i];
    group[i] =
        group_of.try_emplace(std::make_tuple(m.amplitude_v, m.frequency_hz, m.load_n), group_of.size()).first->second;
  }
  const std::size_t points = group_of.size();
  std::vector<std::size_t> permutation(points);
  std::iota(permutation.begin(), permutation.end(), std::size_t{0});
  std::mt19937_64 rng(options.seed);
  for (std::size_t i = permutation.size(); i > 1; --i) {  // Fisher-Yates, portable
    std::swap(permutation[i - 1], permutation[rng() % i]);
  }
  const auto by_fraction = static_cast<std::size_t>(std::ceil(options.fraction * static_cast<double>(points)));
  const std::size_t count = std::max(by_fraction,
                                     std::min(static_cast<std::size_t>(std::max(options.min_points, 0)), points / 2));
  std::vector<bool> held_group(points, false);
  for (std::size_t k = 0; k < std::min(count, points); ++k) held_group[permutation[k]] = true;
  std::vector<bool> held(set.rows.size());
  for (std::size_t i = 0; i < held.size(); ++i) held[i] = held_group[group[i]];
  held_points = static_cast<int>(std::min(count, points));
  point_count = static_cast<int>(points);
  return held;
}

}  // namespace swum
