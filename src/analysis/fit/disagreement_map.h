// Where a model and measurements disagree (docs/discrepancy.md): relative residuals of every
// measured value, where they are largest, trend tests against voltage, frequency, load,
// session time and measured amplitude, and a noise estimate (from repeated readings of one
// operating point, else from successive differences along each sweep, else from what a smooth
// quadratic surface in the operating point cannot explain).
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/measurements/measured_point_model.h"
#include "analysis/measurements/measurements.h"

namespace swum {

// One measured value: row of the set and quantity.
struct ResidualSlot {
  std::size_t row = 0;
  Quantity quantity = Quantity::speed;
};

// Relative residual r = (predicted - measured) / max(|measured|, floor_q), floor_q =
// floor_fraction x the largest |measured| of that quantity (so values near zero, e.g. in the
// dead zone, are compared on the quantity's scale). A diverged prediction counts r = 1.
class ResidualModel {
 public:
  ResidualModel(const MeasurementSet& set, double floor_fraction);
  [[nodiscard]] const std::vector<ResidualSlot>& slots() const { return slots_; }
  [[nodiscard]] double residual(std::size_t slot, const Predictions& predicted) const;
  [[nodiscard]] std::vector<double> residuals(const Predictions& predicted) const;
  [[nodiscard]] double measured(std::size_t slot) const;
  [[nodiscard]] const MeasurementSet& set() const { return *set_; }

 private:
  const MeasurementSet* set_;
  std::array<double, kQuantityCount> floor_{};
  std::vector<ResidualSlot> slots_;
};

struct ResidualValue {
  ResidualSlot slot;
  double measured = 0.0;
  double predicted = 0.0;
  double relative = 0.0;
};

// Residual against one variable of the operating point: quadratic regression r ~ 1 + x + x^2
// per quantity; the largest F statistic (2 and n-3 degrees of freedom) over the quantities.
struct TrendTest {
  std::string_view variable;  // "amplitude_v", "frequency", "load", "time", "amplitude"
  double f_statistic = 0.0;
  double explained_fraction = 0.0;  // R^2 of that regression
  Quantity quantity = Quantity::speed;
  bool structured = false;  // F above the threshold
};

struct QuantityStatistics {
  int count = 0;
  double rms = 0.0;      // relative
  double max_abs = 0.0;  // relative
  double mean = 0.0;     // relative (bias)
};

struct DisagreementMap {
  std::vector<ResidualValue> residuals;
  double rms = 0.0;  // all quantities, relative
  std::array<QuantityStatistics, kQuantityCount> by_quantity{};
  std::vector<ResidualValue> largest;  // the 5 largest |r|
  std::vector<TrendTest> trends;
  double noise = 0.0;         // relative noise estimate (standard deviation)
  std::string noise_source;   // repeats, differences along the sweeps, or a quadratic surface
  double robust_scale = 0.0;  // 1.4826 median |r|
  double excess = 0.0;        // robust_scale / noise
  bool structured = false;    // a trend, or rms clearly above the noise
  std::string summary;        // one sentence: structured (where) or within the noise
};

inline constexpr double kTrendThresholdF = 12.0;  // p ~ 1e-5 for (2, 60) degrees of freedom

[[nodiscard]] DisagreementMap map_disagreement(const MeasurementSet& set, const Predictions& predicted,
                                               const ResidualModel& residuals, std::span<const std::size_t> rows = {});

}  // namespace swum
