// A Monte-Carlo motor population (`swum population`, docs/population.md): the parameters of
// motor i drawn from a counter-based stream keyed by (study seed, i), and the statistics of
// the operating points over the population. Pure: no I/O, no threads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "formats/spread_file.h"
#include "model/parameters.h"

namespace swum {

/// The values of motor `motor`, one per spread, in the order of `spreads`. Each value comes
/// from Philox4x64-10 (Random123) with key (seed, a constant) and counter (motor, the
/// parameter's stream, attempt, 0): a function of (seed, motor, parameter name) alone, so
/// the order, thread or rank in which motors are drawn changes nothing. A normal draw beyond
/// its truncation takes the next attempt (acceptance >= 38 % at the smallest truncation).
[[nodiscard]] std::vector<double> draw_spread_values(const std::vector<ParameterSpread>& spreads, std::uint64_t seed,
                                                     std::uint64_t motor);

/// `nominal` with each spread's parameter set to its drawn value.
[[nodiscard]] MotorParameters with_drawn_values(MotorParameters nominal, const std::vector<ParameterSpread>& spreads,
                                                const std::vector<double>& values);

struct Distribution {
  std::size_t count = 0;  // values described (0: the numbers below are meaningless)
  double min = 0.0, p5 = 0.0, p50 = 0.0, p95 = 0.0, max = 0.0;
};

/// Min, 5th, 50th, 95th percentile and max; percentiles interpolate linearly between order
/// statistics (position p (n - 1), as numpy's default).
[[nodiscard]] Distribution describe_distribution(std::vector<double> values);

struct FrequencyBand {
  bool reached = false;  // false: fewer motors than `needed` can be covered at all
  double low_hz = 0.0, high_hz = 0.0;
  std::size_t needed = 0;   // ceil(yield x motors)
  std::size_t covered = 0;  // motors whose whole span lies in [low, high] (>= needed)
};

/// The narrowest interval [low, high] that holds the whole span of at least ceil(yield x
/// `motors`) motors. A motor's span is [lowest, highest] of its operating frequencies over the
/// voltages; std::nullopt = a motor that cannot be covered (rejected or undecided at some
/// voltage), which counts in `motors` but never in `covered`. Ties: the lowest interval.
[[nodiscard]] FrequencyBand narrowest_band(const std::vector<std::optional<std::pair<double, double>>>& spans,
                                           double yield);

}  // namespace swum
