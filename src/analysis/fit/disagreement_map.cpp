#include "analysis/fit/disagreement_map.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>

namespace swum {

ResidualModel::ResidualModel(const MeasurementSet& set, double floor_fraction) : set_(&set) {
  for (std::size_t i = 0; i < set.rows.size(); ++i) {
    for (Quantity q : kQuantities) {
      const auto& v = set.rows[i].value(q);
      if (!v) continue;
      slots_.push_back({i, q});
      auto& f = floor_[static_cast<std::size_t>(q)];
      f = std::max(f, floor_fraction * std::abs(*v));
    }
  }
  for (double& f : floor_) f = std::max(f, 1e-12);
}

double ResidualModel::measured(std::size_t slot) const {
  const ResidualSlot& s = slots_[slot];
  return *set_->rows[s.row].value(s.quantity);
}

double ResidualModel::residual(std::size_t slot, const Predictions& predicted) const {
  const ResidualSlot& s = slots_[slot];
  const PredictedPoint& p = predicted[s.row];
  if (!p.ok) return 1.0;
  const double m = measured(slot);
  return (p.value(s.quantity) - m) / std::max(std::abs(m), floor_[static_cast<std::size_t>(s.quantity)]);
}

std::vector<double> ResidualModel::residuals(const Predictions& predicted) const {
  std::vector<double> r(slots_.size());
  for (std::size_t k = 0; k < slots_.size(); ++k) r[k] = residual(k, predicted);
  return r;
}

namespace {

// Sum of squares left by least squares of y on the columns of x.
double residual_sum_of_squares(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  if (x.rows() <= x.cols()) return 0.0;
  const Eigen::VectorXd beta = x.colPivHouseholderQr().solve(y);
  return (y - x * beta).squaredNorm();
}

// Columns standardised so the regression is well conditioned.
Eigen::VectorXd standardised(Eigen::VectorXd v) {
  const double mean = v.mean();
  const double sd = std::sqrt((v.array() - mean).square().mean());
  v.array() -= mean;
  if (sd > 0.0) v /= sd;
  return v;
}

}  // namespace

DisagreementMap map_disagreement(const MeasurementSet& set, const Predictions& predicted, const ResidualModel& model,
                                 std::span<const std::size_t> rows) {
  DisagreementMap map;
  std::vector<bool> use(set.rows.size(), rows.empty());
  for (std::size_t r : rows) use[r] = true;
  for (std::size_t k = 0; k < model.slots().size(); ++k) {
    const ResidualSlot& s = model.slots()[k];
    if (!use[s.row]) continue;
    map.residuals.push_back({s, model.measured(k), predicted[s.row].value(s.quantity), model.residual(k, predicted)});
  }
  const std::size_t n = map.residuals.size();
  if (n == 0) {
    map.summary = "no measured values";
    return map;
  }
  double sum2 = 0.0;
  for (const ResidualValue& r : map.residuals) {
    sum2 += r.relative * r.relative;
    auto& q = map.by_quantity[static_cast<std::size_t>(r.slot.quantity)];
    ++q.count;
    q.rms += r.relative * r.relative;
    q.mean += r.relative;
    q.max_abs = std::max(q.max_abs, std::abs(r.relative));
  }
  map.rms = std::sqrt(sum2 / static_cast<double>(n));
  for (auto& q : map.by_quantity) {
    if (q.count == 0) continue;
    q.rms = std::sqrt(q.rms / q.count);
    q.mean /= q.count;
  }
  map.largest = map.residuals;
  std::sort(map.largest.begin(), map.largest.end(),
            [](const ResidualValue& a, const ResidualValue& b) { return std::abs(a.relative) > std::abs(b.relative); });
  if (map.largest.size() > 5) map.largest.resize(5);

  // Per quantity: vectors of the residual and of each variable.
  const std::array<std::string_view, 5> variables{"amplitude_v", "frequency", "load", "time", "amplitude"};
  auto variable_of = [&](const ResidualValue& r, std::size_t v) {
    const Measurement& m = set.rows[r.slot.row];
    switch (v) {
      case 0: return m.amplitude_v;
      case 1: return m.frequency_hz;
      case 2: return m.load_n;
      case 3: return m.time_s.value_or(0.0);
      default: return r.measured;
    }
  };
  for (std::size_t v = 0; v < variables.size(); ++v) {
    if (v == 3 && !set.has_time) continue;
    TrendTest best{variables[v]};
    for (Quantity q : kQuantities) {
      std::vector<const ResidualValue*> sel;
      for (const auto& r : map.residuals) {
        if (r.slot.quantity == q) sel.push_back(&r);
      }
      const auto m = static_cast<Eigen::Index>(sel.size());
      if (m < 8) continue;
      Eigen::VectorXd x(m), y(m);
      for (Eigen::Index i = 0; i < m; ++i) {
        x[i] = variable_of(*sel[static_cast<std::size_t>(i)], v);
        y[i] = sel[static_cast<std::size_t>(i)]->relative;
      }
      x = standardised(x);
      if (x.squaredNorm() == 0.0) continue;  // the variable does not vary
      Eigen::MatrixXd design(m, 3);
      design.col(0).setOnes();
      design.col(1) = x;
      design.col(2) = standardised(x.array().square().matrix());
      const double ss0 = (y.array() - y.mean()).square().sum();
      const double ss1 = residual_sum_of_squares(design, y);
      if (ss0 <= 0.0 || ss1 <= 0.0) continue;
      const double f = ((ss0 - ss1) / 2.0) / (ss1 / static_cast<double>(m - 3));
      if (f > best.f_statistic) {
        best.f_statistic = f;
        best.explained_fraction = 1.0 - ss1 / ss0;
        best.quantity = q;
      }
    }
    best.structured = best.f_statistic > kTrendThresholdF;
    map.trends.push_back(best);
  }

  // Noise, in this order of preference (docs/discrepancy.md, "Disagreement map"):
  // 1. the pooled scatter of repeated readings of one operating point (whatever their time: the
  //    residual, not the reading, so a drift the model predicts cancels);
  // 2. along each curve (readings of one voltage, load and sweep, ordered by frequency): the
  //    robust scale of successive residual differences, 1.4826 median|dr| / sqrt(2) - a smooth
  //    model error cancels in the differences, and the median ignores the few steps across a
  //    resonance peak or a dead-zone edge, so structure is not counted as noise;
  // 3. what a quadratic surface in (amplitude_v, frequency, load[, time]) leaves (an upper bound: any
  //    structure a quadratic cannot follow counts as noise).
  std::map<std::tuple<int, double, double, double>, std::vector<double>> groups;
  std::map<std::tuple<int, double, double, int>, std::vector<std::pair<double, double>>> curves;
  for (const auto& r : map.residuals) {
    const Measurement& m = set.rows[r.slot.row];
    groups[{static_cast<int>(r.slot.quantity), m.amplitude_v, m.frequency_hz, m.load_n}].push_back(r.relative);
    curves[{static_cast<int>(r.slot.quantity), m.amplitude_v, m.load_n, m.sweep.value_or(-1)}].emplace_back(
        m.frequency_hz, r.relative);
  }
  double within = 0.0;
  int dof = 0;
  for (const auto& [key, values] : groups) {
    if (values.size() < 2) continue;
    double mean = 0.0;
    for (double x : values) mean += x;
    mean /= static_cast<double>(values.size());
    for (double x : values) within += (x - mean) * (x - mean);
    dof += static_cast<int>(values.size()) - 1;
  }
  std::vector<double> steps;  // |successive differences| along curves of distinct frequencies
  for (auto& [key, points] : curves) {
    std::sort(points.begin(), points.end());
    for (std::size_t i = 1; i < points.size(); ++i) {
      if (points[i].first != points[i - 1].first) steps.push_back(std::abs(points[i].second - points[i - 1].second));
    }
  }
  constexpr std::size_t kMinSteps = 12;
  if (dof >= 5) {
    map.noise = std::sqrt(within / dof);
    map.noise_source = "repeats";
  } else if (steps.size() >= kMinSteps) {
    auto mid = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
    std::nth_element(steps.begin(), mid, steps.end());
    map.noise = 1.4826 * *mid / std::sqrt(2.0);
    map.noise_source = "differences along the sweeps";
  } else {
    double ss = 0.0;
    int free = 0;
    bool any_regression = false;  // false: too few values to separate trend from noise
    for (Quantity q : kQuantities) {
      std::vector<const ResidualValue*> sel;
      for (const auto& r : map.residuals) {
        if (r.slot.quantity == q) sel.push_back(&r);
      }
      const auto m = static_cast<Eigen::Index>(sel.size());
      const int nv = set.has_time ? 4 : 3;
      const Eigen::Index terms = 1 + nv + nv * (nv + 1) / 2;
      if (m <= terms + 2) {
        for (const auto* r : sel) ss += r->relative * r->relative;
        free += static_cast<int>(m);
        continue;
      }
      Eigen::MatrixXd design(m, terms);
      std::vector<Eigen::VectorXd> cols;
      for (int v = 0; v < nv; ++v) {
        Eigen::VectorXd x(m);
        for (Eigen::Index i = 0; i < m; ++i)
          x[i] = variable_of(*sel[static_cast<std::size_t>(i)], static_cast<std::size_t>(v));
        cols.push_back(standardised(x));
      }
      Eigen::Index c = 0;
      design.col(c++).setOnes();
      for (int a = 0; a < nv; ++a) design.col(c++) = cols[static_cast<std::size_t>(a)];
      for (int a = 0; a < nv; ++a) {
        for (int b = a; b < nv; ++b) {
          design.col(c++) = cols[static_cast<std::size_t>(a)].cwiseProduct(cols[static_cast<std::size_t>(b)]);
        }
      }
      Eigen::VectorXd y(m);
      for (Eigen::Index i = 0; i < m; ++i) y[i] = sel[static_cast<std::size_t>(i)]->relative;
      any_regression = true;
      const Eigen::Index rank = design.colPivHouseholderQr().rank();
      ss += residual_sum_of_squares(design, y);
      free += static_cast<int>(m - rank);
    }
    map.noise = free > 0 ? std::sqrt(ss / free) : map.rms;
    map.noise_source = any_regression ? "what a quadratic surface leaves, an upper bound"
                                      : "too few points to separate noise from trends: the whole residual";
  }
  // The residual's own scale, robustly (1.4826 median|r|: a few wild readings near a collapse
  // do not make noise look like structure), against the noise: (scale/noise)^2 is ~1 under
  // pure noise, with a relative variance of about 5.44/n for the median estimate (asymptotic
  // efficiency 37 %); structured when 4 of its standard deviations above 1.
  std::vector<double> magnitudes;
  for (const ResidualValue& r : map.residuals) magnitudes.push_back(std::abs(r.relative));
  auto middle = magnitudes.begin() + static_cast<std::ptrdiff_t>(magnitudes.size() / 2);
  std::nth_element(magnitudes.begin(), middle, magnitudes.end());
  map.robust_scale = 1.4826 * *middle;
  map.excess = map.noise > 0.0 ? map.robust_scale / map.noise : 0.0;
  const bool above_noise = map.excess * map.excess > 1.0 + 4.0 * std::sqrt(5.44 / static_cast<double>(n));
  const TrendTest* strongest = nullptr;
  for (const TrendTest& t : map.trends) {
    if (t.structured && (strongest == nullptr || t.f_statistic > strongest->f_statistic)) strongest = &t;
  }
  map.structured = above_noise || strongest != nullptr;
  char text[400];
  if (map.structured) {
    std::snprintf(text, sizeof text, "structured: RMS %.3g %% (robust scale %.3g %%) vs noise %.3g %% (%s)%s%s%s",
                  100.0 * map.rms, 100.0 * map.robust_scale, 100.0 * map.noise, map.noise_source.c_str(),
                  strongest != nullptr ? "; strongest trend of " : "",
                  strongest != nullptr ? std::string(quantity_column(strongest->quantity)).c_str() : "",
                  strongest != nullptr ? (" against " + std::string(strongest->variable)).c_str() : "");
  } else {
    std::snprintf(text, sizeof text,
                  "within the noise: RMS %.3g %% (robust scale %.3g %%) vs noise %.3g %% (%s), no trend",
                  100.0 * map.rms, 100.0 * map.robust_scale, 100.0 * map.noise, map.noise_source.c_str());
  }
  map.summary = text;
  return map;
}

}  // namespace swum
