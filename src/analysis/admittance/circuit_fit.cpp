#include "analysis/admittance/circuit_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace swum {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kUnknowns = static_cast<int>(kCircuitFitUnknowns);

using Theta = std::array<double, kUnknowns>;  // log(value / scale) of C0, then R_m, L_m, C_m of each mode

// One point's complex residual (Y_circuit - Y)/|Y| from theta.
struct PointResidual {
  double omega, g, b, inverse_magnitude;
  std::array<double, kUnknowns> scale;

  template <typename T>
  bool operator()(const T* theta, T* r) const {
    const T w(omega);
    T re(0.0);
    T im = w * scale[0] * exp(theta[0]);
    for (std::size_t i = 0; i < kCircuitModes; ++i) {
      const T rr = scale[1 + 3 * i] * exp(theta[1 + 3 * i]);
      const T l = scale[2 + 3 * i] * exp(theta[2 + 3 * i]);
      const T c = scale[3 + 3 * i] * exp(theta[3 + 3 * i]);
      const T x = w * l - 1.0 / (w * c);
      const T d = rr * rr + x * x;
      re += rr / d;
      im -= x / d;
    }
    r[0] = (re - g) * inverse_magnitude;
    r[1] = (im - b) * inverse_magnitude;
    return true;
  }
};

struct Data {
  std::vector<double> f, g, b;
};

// Linear interpolation of where y crosses `level` between samples i and j.
double crossing(const Data& d, std::size_t i, std::size_t j, double level) {
  const double t = (level - d.g[i]) / (d.g[j] - d.g[i]);
  return d.f[i] + t * (d.f[j] - d.f[i]);
}

// A conductance peak: its frequency, height and width at half height (from the crossings on
// both sides, twice the one found, or half the grid when neither is).
struct Peak {
  double frequency_hz = 0.0, conductance_siemens = 0.0, width_hz = 0.0;
};

Peak peak_at(const Data& d, std::size_t peak) {
  const std::size_t n = d.f.size();
  Peak p{d.f[peak], d.g[peak], 0.0};
  const double half = 0.5 * p.conductance_siemens;
  double low = NAN, high = NAN;
  for (std::size_t i = peak; i > 0; --i) {
    if (d.g[i - 1] < half) {
      low = crossing(d, i - 1, i, half);
      break;
    }
  }
  for (std::size_t i = peak; i + 1 < n; ++i) {
    if (d.g[i + 1] < half) {
      high = crossing(d, i, i + 1, half);
      break;
    }
  }
  if (std::isfinite(low) && std::isfinite(high)) {
    p.width_hz = high - low;
  } else if (std::isfinite(low)) {
    p.width_hz = 2.0 * (p.frequency_hz - low);
  } else if (std::isfinite(high)) {
    p.width_hz = 2.0 * (high - p.frequency_hz);
  } else {
    p.width_hz = 0.5 * (d.f.back() - d.f.front());
  }
  p.width_hz = std::max(p.width_hz, 1e-6 * p.frequency_hz);
  return p;
}

// A branch with conductance share `share` of the peak, at `frequency_hz`, with the peak's
// width stretched by `stretch` (G_max = 1/R, Q = fs/width, L = R Q/(2 pi fs)).
MotionalBranch branch_from(const Peak& p, double share, double frequency_hz, double stretch) {
  MotionalBranch b;
  b.resistance_ohm = 1.0 / (share * p.conductance_siemens);
  b.inductance_h = b.resistance_ohm / (kTwoPi * p.width_hz * stretch);
  b.capacitance_f = 1.0 / (std::pow(kTwoPi * frequency_hz, 2) * b.inductance_h);
  return b;
}

// C0 from B/w at the grid's two ends: the motional susceptance has opposite signs below and
// above the resonance, so their mean cancels it to first order.
double clamped_capacitance_guess_f(const Data& d) {
  return 0.5 * (d.b.front() / (kTwoPi * d.f.front()) + d.b.back() / (kTwoPi * d.f.back()));
}

// Overlapping modes (one conductance peak): the highest peak split into two branches sharing
// its conductance equally, detuned by +-`detune` of its width, widths in ratio `width_ratio`.
EquivalentCircuit guess_overlapping(const Data& d, double detune, double width_ratio) {
  EquivalentCircuit c;
  c.clamped_capacitance_f = clamped_capacitance_guess_f(d);
  const Peak p = peak_at(d, static_cast<std::size_t>(std::max_element(d.g.begin(), d.g.end()) - d.g.begin()));
  c.branches[0] = branch_from(p, 0.5, p.frequency_hz + detune * p.width_hz, std::sqrt(width_ratio));
  c.branches[1] = branch_from(p, 0.5, p.frequency_hz - detune * p.width_hz, 1.0 / std::sqrt(width_ratio));
  return c;
}

// Separate modes: the two highest local maxima of the conductance, one branch each. Empty
// when the conductance has fewer than two interior maxima.
std::optional<EquivalentCircuit> guess_separate(const Data& d) {
  std::vector<std::size_t> maxima;
  for (std::size_t i = 1; i + 1 < d.g.size(); ++i) {
    if (d.g[i] > d.g[i - 1] && d.g[i] >= d.g[i + 1]) maxima.push_back(i);
  }
  if (maxima.size() < 2) return std::nullopt;
  std::partial_sort(maxima.begin(), maxima.begin() + 2, maxima.end(),
                    [&](std::size_t i, std::size_t j) { return d.g[i] > d.g[j]; });
  EquivalentCircuit c;
  c.clamped_capacitance_f = clamped_capacitance_guess_f(d);
  for (std::size_t k = 0; k < kCircuitModes; ++k) {
    const Peak p = peak_at(d, maxima[k]);
    c.branches[k] = branch_from(p, 1.0, p.frequency_hz, 1.0);
  }
  return c;
}

Theta scales_of(const EquivalentCircuit& c) {
  Theta s{};
  s[0] = c.clamped_capacitance_f;
  for (std::size_t i = 0; i < kCircuitModes; ++i) {
    s[1 + 3 * i] = c.branches[i].resistance_ohm;
    s[2 + 3 * i] = c.branches[i].inductance_h;
    s[3 + 3 * i] = c.branches[i].capacitance_f;
  }
  return s;
}

EquivalentCircuit circuit_of(const Theta& v) {
  EquivalentCircuit c;
  c.clamped_capacitance_f = v[0];
  for (std::size_t i = 0; i < kCircuitModes; ++i) {
    c.branches[i] = {v[1 + 3 * i], v[2 + 3 * i], v[3 + 3 * i]};
  }
  return c;
}

struct Solve {
  bool usable = false;
  double cost = INFINITY;
  int iterations = 0;
  Theta scale{}, theta{};
  std::vector<double> covariance;  // kUnknowns^2 of theta, unscaled (J^T J)^-1
};

Solve solve_from(const Data& d, const EquivalentCircuit& start, int max_iterations) {
  Solve s;
  s.scale = scales_of(start);
  for (double v : s.scale) {
    if (!(std::isfinite(v) && v > 0.0)) return s;
  }
  ceres::Problem problem;
  for (std::size_t k = 0; k < d.f.size(); ++k) {
    const double magnitude = std::hypot(d.g[k], d.b[k]);
    auto* cost = new ceres::AutoDiffCostFunction<PointResidual, 2, kUnknowns>(
        new PointResidual{kTwoPi * d.f[k], d.g[k], d.b[k], 1.0 / magnitude, s.scale});
    problem.AddResidualBlock(cost, nullptr, s.theta.data());
  }
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = max_iterations;
  so.function_tolerance = 1e-15;
  so.gradient_tolerance = 1e-16;
  so.parameter_tolerance = 1e-14;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  s.iterations = static_cast<int>(summary.iterations.size());
  s.cost = summary.final_cost;
  s.usable = summary.IsSolutionUsable() && std::isfinite(s.cost);
  if (!s.usable) return s;
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  // 0: a singular J^T J (an element the data do not determine) fails Compute, and every error is
  // then infinite; a pseudo-inverse (-1) would drop that direction and report a tiny error.
  co.null_space_rank = 0;
  ceres::Covariance covariance(co);
  std::vector<std::pair<const double*, const double*>> blocks = {{s.theta.data(), s.theta.data()}};
  if (covariance.Compute(blocks, &problem)) {
    s.covariance.assign(kUnknowns * kUnknowns, 0.0);
    covariance.GetCovarianceBlock(s.theta.data(), s.theta.data(), s.covariance.data());
  }
  return s;
}

}  // namespace

CircuitFit fit_equivalent_circuit(std::span<const AdmittancePoint> points, const CircuitFitOptions& options) {
  CircuitFit out;
  std::vector<const AdmittancePoint*> sorted;
  for (const AdmittancePoint& p : points) {
    if (!p.diverged && std::isfinite(p.conductance_siemens) && std::isfinite(p.susceptance_siemens) &&
        p.magnitude_siemens > 0.0 && p.frequency_hz > 0.0)
      sorted.push_back(&p);
  }
  std::sort(sorted.begin(), sorted.end(),
            [](const AdmittancePoint* x, const AdmittancePoint* y) { return x->frequency_hz < y->frequency_hz; });
  out.points = static_cast<int>(sorted.size());
  if (sorted.size() < kCircuitFitMinimumPoints) {
    out.failure = "fewer than " + std::to_string(kCircuitFitMinimumPoints) + " usable points";
    return out;
  }
  Data d;
  for (const AdmittancePoint* p : sorted) {
    d.f.push_back(p->frequency_hz);
    d.g.push_back(p->conductance_siemens);
    d.b.push_back(p->susceptance_siemens);
  }
  // A few detunings and width ratios of the two branches: the symmetric split is a saddle.
  Solve best;
  EquivalentCircuit best_start;
  std::vector<EquivalentCircuit> starts;
  for (double detune : {0.05, 0.15, 0.3}) {
    for (double ratio : {1.0, 1.6, 1.0 / 1.6}) starts.push_back(guess_overlapping(d, detune, ratio));
  }
  if (const auto separate = guess_separate(d)) starts.push_back(*separate);
  for (const EquivalentCircuit& start : starts) {
    Solve s = solve_from(d, start, options.max_iterations);
    if (s.usable && s.cost < best.cost) {
      best = std::move(s);
      best_start = start;
    }
  }
  if (!best.usable) {
    out.failure = "the least-squares solve failed from every start";
    return out;
  }
  Theta value{}, error{};
  for (int k = 0; k < kUnknowns; ++k) value[k] = best.scale[k] * std::exp(best.theta[k]);
  const int dof = 2 * out.points - kUnknowns;
  const double variance = 2.0 * best.cost / dof;  // ceres cost = sum r^2 / 2
  for (int k = 0; k < kUnknowns; ++k) {
    error[k] = best.covariance.empty()
                   ? INFINITY
                   : value[k] * std::sqrt(std::max(0.0, variance * best.covariance[k * kUnknowns + k]));
  }
  out.circuit = circuit_of(value);
  out.standard_error = circuit_of(error);
  out.start = best_start;
  // Label the branches (CircuitFitOptions::reference_inductance_h).
  const auto& ref = options.reference_inductance_h;
  const bool ref_ascending = !(ref[0] > 0.0 && ref[1] > 0.0) || ref[0] < ref[1];
  const bool swap = (out.circuit.branches[0].inductance_h < out.circuit.branches[1].inductance_h) != ref_ascending;
  if (swap) {
    std::swap(out.circuit.branches[0], out.circuit.branches[1]);
    std::swap(out.standard_error.branches[0], out.standard_error.branches[1]);
    std::swap(out.start.branches[0], out.start.branches[1]);
  }
  out.rms_relative_residual = std::sqrt(2.0 * best.cost / out.points);
  out.iterations = best.iterations;
  out.ok = true;
  return out;
}

}  // namespace swum
