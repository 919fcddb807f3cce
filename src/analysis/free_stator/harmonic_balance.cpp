#include "analysis/free_stator/harmonic_balance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Dense>

namespace swum {
namespace {

constexpr double kMicro = 1e6;  // unknowns are solved in micrometres (§6.2: "scale to um")

// Real roots in (0, 1] of g(y) = y ((kappa y + delta)^2 + 1) - 1 (§6.3 cubic in A^2, made
// dimensionless with A_ref = F/(C w)); g(0) = -1 and g(1) >= 0, so every root lies there.
std::vector<double> normalised_cubic_roots(double kappa, double delta) {
  auto g = [&](double y) {
    const double t = kappa * y + delta;
    return y * (t * t + 1.0) - 1.0;
  };
  std::vector<double> breaks{0.0};
  if (std::abs(kappa) > 1e-300 && delta * delta > 3.0) {
    // g'(y) = 3 kappa^2 y^2 + 4 kappa delta y + delta^2 + 1 = 0
    const double root = std::abs(kappa) * std::sqrt(delta * delta - 3.0);
    for (double y : {(-2.0 * kappa * delta - root) / (3.0 * kappa * kappa),
                     (-2.0 * kappa * delta + root) / (3.0 * kappa * kappa)}) {
      if (y > 0.0 && y < 1.0) breaks.push_back(y);
    }
  }
  breaks.push_back(1.0);
  std::sort(breaks.begin(), breaks.end());
  std::vector<double> roots;
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
    double lo = breaks[i];
    double hi = breaks[i + 1];
    double glo = g(lo);
    const double ghi = g(hi);
    if (glo == 0.0) {
      if (lo > 0.0) roots.push_back(lo);
      continue;
    }
    if ((glo < 0.0) == (ghi < 0.0)) continue;
    for (int k = 0; k < 200 && hi - lo > 1e-15 * hi; ++k) {  // g is monotone in [lo, hi]
      const double mid = 0.5 * (lo + hi);
      const double gm = g(mid);
      if ((gm < 0.0) == (glo < 0.0)) {
        lo = mid;
        glo = gm;
      } else {
        hi = mid;
      }
    }
    roots.push_back(0.5 * (lo + hi));
  }
  return roots;
}

bool same_solution(const ModeHarmonics& x, const ModeHarmonics& y) {
  const double scale = std::max({x.amplitude_m(), y.amplitude_m(), 1e-12});
  return std::abs(x.offset_m - y.offset_m) < 1e-6 * scale && std::abs(x.cos_m - y.cos_m) < 1e-6 * scale &&
         std::abs(x.sin_m - y.sin_m) < 1e-6 * scale;
}

double distance(const ModeHarmonics& x, const ModeHarmonics& y) {
  return std::hypot(x.offset_m - y.offset_m, x.cos_m - y.cos_m, x.sin_m - y.sin_m);
}

}  // namespace

double ModeHarmonics::amplitude_m() const { return std::hypot(cos_m, sin_m); }

FreeStatorHarmonicBalance::FreeStatorHarmonicBalance(const ModalConstants& c, const StatorParameters& stator,
                                                     const HarmonicBalanceOptions& options)
    : options_(options), amplitude_per_volt_(c.drive_amplitude_per_volt) {
  const StatorForceCoefficients f = make_stator_force_coefficients(c, stator);
  Mode& l1 = modes_[0];
  l1.mass_kg = c.m1_kg;
  l1.damping_n_s_m = c.c1_n_s_m;
  l1.tip_lever = 1.0;  // |phiL(L)|
  l1.force = f.l1;
  l1.electrical = c.a;
  l1.cubic_shape = c.beta1_per_m;
  l1.quadratic_shape = c.alpha1;
  Mode& b2 = modes_[1];
  b2.mass_kg = c.m2_kg;
  b2.damping_n_s_m = c.c2_n_s_m;
  b2.tip_lever = std::abs(c.phi_b_tip);  // eq. 30: W = phiB(L) A2
  b2.force = f.b2;
  b2.electrical = c.b;
  b2.cubic_shape = c.beta2_per_m;
  b2.quadratic_shape = 0.0;
  for (Mode& mode : modes_) {  // the thermal effect, as MotorSimulator applies it (motor.h set_modal_factors)
    mode.force.k *= options.stiffness_factor;
    mode.damping_n_s_m *= options.damping_factor;
  }
  const double phase = options.phase_deg * std::numbers::pi / 180.0;
  cos_phase_ = std::cos(phase);
  sin_phase_ = std::sin(phase);
  const int n = std::max(options.samples_per_period, 5);
  options_.samples_per_period = n;
  cos_table_.resize(n);
  sin_table_.resize(n);
  for (int i = 0; i < n; ++i) {
    const double th = 2.0 * std::numbers::pi * i / n;
    cos_table_[i] = std::cos(th);
    sin_table_[i] = std::sin(th);
  }
}

FreeStatorHarmonicBalance::FreeStatorHarmonicBalance(const MotorModel& model, const HarmonicBalanceOptions& options)
    : FreeStatorHarmonicBalance(model.constants(), with_static_effects(model.parameters()).stator, options) {}

double FreeStatorHarmonicBalance::tip_lever(StatorMode mode) const { return mode_data(mode).tip_lever; }

FreeStatorHarmonicBalance::Drive FreeStatorHarmonicBalance::drive(double amplitude_v, double frequency_hz) const {
  return {amplitude_per_volt_ * amplitude_v, 2.0 * std::numbers::pi * frequency_hz};
}

std::vector<ModeHarmonics> FreeStatorHarmonicBalance::closed_form_seeds(StatorMode which, double amplitude_v,
                                                                        double frequency_hz) const {
  // §6.3 with the DC offset of the quadratic terms kept (first harmonic + DC, as the AFT).
  const Mode& mode = mode_data(which);
  const ModeForceCoefficients& m = mode.force;
  const Drive d = drive(amplitude_v, frequency_hz);
  const double v0 = d.amplitude_v;
  const double w = d.omega_rad_s;
  // First harmonic of c0(t) = lin0_a V_A + lin0_b V_B (V_A = V0 sin wt, V_B = V0 sin(wt+phi)).
  const double f_cos = v0 * m.lin0_b * sin_phase_;
  const double f_sin = v0 * (m.lin0_a + m.lin0_b * cos_phase_);
  const double f_dc = 0.5 * (m.sq0_a + m.sq0_b) * v0 * v0;         // <e311 X1(t)>
  const double k_eff = m.k - 0.5 * (m.sq1_a + m.sq1_b) * v0 * v0;  // K - e3111 <X3(t)>
  const double k_first = k_eff + 2.0 * m.k2 * f_dc / k_eff;
  const double k3_eff = 0.75 * m.k3 - m.k2 * m.k2 / k_eff;  // cubic + DC-mediated quadratic
  const double cw = mode.damping_n_s_m * w;
  const double detuning = k_first - mode.mass_kg * w * w;
  const double force2 = f_cos * f_cos + f_sin * f_sin;
  std::vector<ModeHarmonics> seeds;
  if (force2 == 0.0) {
    seeds.push_back({f_dc / k_eff, 0.0, 0.0});
    return seeds;
  }
  const double x_ref = force2 / (cw * cw);  // A_ref^2, A_ref = F/(C w)
  const double kappa = k3_eff * x_ref / cw;
  const double delta = detuning / cw;
  for (double y : normalised_cubic_roots(kappa, delta)) {
    const double x = x_ref * y;
    const double de = detuning + k3_eff * x;
    const double det = de * de + cw * cw;
    seeds.push_back(
        {(f_dc - 0.5 * m.k2 * x) / k_eff, (de * f_cos - cw * f_sin) / det, (de * f_sin + cw * f_cos) / det});
  }
  std::sort(seeds.begin(), seeds.end(),
            [](const ModeHarmonics& x, const ModeHarmonics& y) { return x.amplitude_m() > y.amplitude_m(); });
  return seeds;
}

bool FreeStatorHarmonicBalance::polish(StatorMode which, double amplitude_v, double frequency_hz,
                                       const ModeHarmonics& guess, ModeBranch& out) const {
  const Mode& mode = mode_data(which);
  const ModeForceCoefficients& m = mode.force;
  const Drive d = drive(amplitude_v, frequency_hz);
  const double v0 = d.amplitude_v;
  const double w = d.omega_rad_s;
  const double mw2 = mode.mass_kg * w * w;
  const double cw = mode.damping_n_s_m * w;
  const int n = options_.samples_per_period;
  const double inv_n = 1.0 / n;
  // Scaled residual R~ = R * 1e6 / K (um), unknowns x = q * 1e6 (um): J~ = dR/dq / K.
  const double r_scale = kMicro / m.k;
  const double j_scale = 1.0 / m.k;

  double x[3] = {guess.offset_m * kMicro, guess.cos_m * kMicro, guess.sin_m * kMicro};
  double jac[3][3];
  auto evaluate = [&](const double* u, double* r, bool with_jacobian) {
    const double q0 = u[0] / kMicro, a = u[1] / kMicro, b = u[2] / kMicro;
    double s0 = 0.0, sc = 0.0, ss = 0.0;
    double j00 = 0.0, j0c = 0.0, j0s = 0.0, jcc = 0.0, jcs = 0.0, jss = 0.0;
    for (int i = 0; i < n; ++i) {
      const double c = cos_table_[i];
      const double s = sin_table_[i];
      const double va = v0 * s;
      const double vb = v0 * (s * cos_phase_ + c * sin_phase_);
      const double q = q0 + a * c + b * s;
      const double f = modal_force_n(m, q, va, vb);
      s0 += f;
      sc += f * c;
      ss += f * s;
      if (with_jacobian) {
        const double c1 = m.lin1_a * va + m.lin1_b * vb + m.sq1_a * va * va + m.sq1_b * vb * vb - m.k;
        const double c2 = m.lin2_a * va + m.lin2_b * vb - m.k2;
        const double fp = c1 + q * (2.0 * c2 - 3.0 * m.k3 * q);  // df/dq
        j00 += fp;
        j0c += fp * c;
        j0s += fp * s;
        jcc += fp * c * c;
        jcs += fp * c * s;
        jss += fp * s * s;
      }
    }
    // r(t) = M q'' + C q' - f: projections <r>, 2<r cos>, 2<r sin>.
    r[0] = -s0 * inv_n * r_scale;
    r[1] = (-mw2 * a + cw * b - 2.0 * sc * inv_n) * r_scale;
    r[2] = (-mw2 * b - cw * a - 2.0 * ss * inv_n) * r_scale;
    if (with_jacobian) {
      jac[0][0] = -j00 * inv_n * j_scale;
      jac[0][1] = -j0c * inv_n * j_scale;
      jac[0][2] = -j0s * inv_n * j_scale;
      jac[1][0] = -2.0 * j0c * inv_n * j_scale;
      jac[1][1] = (-mw2 - 2.0 * jcc * inv_n) * j_scale;
      jac[1][2] = (cw - 2.0 * jcs * inv_n) * j_scale;
      jac[2][0] = -2.0 * j0s * inv_n * j_scale;
      jac[2][1] = (-cw - 2.0 * jcs * inv_n) * j_scale;
      jac[2][2] = (-mw2 - 2.0 * jss * inv_n) * j_scale;
    }
  };

  double r[3];
  evaluate(x, r, true);
  double norm = std::abs(r[0]) + std::abs(r[1]) + std::abs(r[2]);
  bool converged = false;
  int iteration = 0;
  for (; iteration < options_.max_newton_iterations; ++iteration) {
    Eigen::Matrix3d jm;
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) jm(i, k) = jac[i][k];
    const Eigen::Vector3d step = jm.partialPivLu().solve(-Eigen::Vector3d(r[0], r[1], r[2]));
    if (!step.allFinite()) return false;
    // Damped Newton: halve the step until the residual does not grow.
    double lambda = 1.0;
    double trial[3];
    double r_trial[3];
    double norm_trial = 0.0;
    for (int halving = 0; halving < 30; ++halving) {
      for (int i = 0; i < 3; ++i) trial[i] = x[i] + lambda * step[i];
      evaluate(trial, r_trial, false);
      norm_trial = std::abs(r_trial[0]) + std::abs(r_trial[1]) + std::abs(r_trial[2]);
      if (std::isfinite(norm_trial) && norm_trial <= norm * (1.0 + 1e-12) + 1e-18) break;
      lambda *= 0.5;
    }
    if (!std::isfinite(norm_trial)) return false;
    std::copy(trial, trial + 3, x);
    evaluate(x, r, true);
    norm = std::abs(r[0]) + std::abs(r[1]) + std::abs(r[2]);
    const double step_size = lambda * step.cwiseAbs().maxCoeff();
    const double scale = 1.0 + std::abs(x[1]) + std::abs(x[2]);
    if (step_size < options_.tolerance_um * scale && norm < 1e-6 * scale) {
      converged = true;
      ++iteration;
      break;
    }
  }
  if (!converged) return false;

  out.harmonics = {x[0] / kMicro, x[1] / kMicro, x[2] / kMicro};
  out.tip_amplitude_um = mode.tip_lever * out.harmonics.amplitude_m() * kMicro;
  out.newton_iterations = iteration;
  // Stability (docs/harmonic_balance.md): DC slaved (J00 > 0), slow flow of (a, b) from the
  // Schur complement: det > 0 and trace < 0.
  const double j00 = jac[0][0];
  bool stable = j00 > 0.0;
  if (stable) {
    const double raa = jac[1][1] - jac[1][0] * jac[0][1] / j00;
    const double rab = jac[1][2] - jac[1][0] * jac[0][2] / j00;
    const double rba = jac[2][1] - jac[2][0] * jac[0][1] / j00;
    const double rbb = jac[2][2] - jac[2][0] * jac[0][2] / j00;
    const double det = raa * rbb - rab * rba;
    const double trace = rba - rab;  // d(a')/da + d(b')/db, up to the factor 1/(2 M w)
    stable = det > 0.0 && trace < 0.0;
  }
  out.stable = stable;
  fill_sensitivities(mode, d, out, jac);
  return true;
}

void FreeStatorHarmonicBalance::fill_sensitivities(const Mode& mode, const Drive& d, ModeBranch& branch,
                                                   const double (&jacobian)[3][3]) const {
  // Implicit function theorem: dx/dp = -J^-1 dR/dp, with dr/dp = -df/dp (eqs. 14-15):
  //   c111: df = -alpha1 q^2, c1111: df = -beta q^3, e311: df = X1(t) + X2(t) q,
  //   e3111: df = X3(t) q + X4(t) q^2.
  const int n = options_.samples_per_period;
  const double inv_n = 1.0 / n;
  const double r_scale = kMicro / mode.force.k;
  const auto& e = mode.electrical;
  const ModeHarmonics& h = branch.harmonics;
  Eigen::Matrix<double, 3, 4> dr = Eigen::Matrix<double, 3, 4>::Zero();
  for (int i = 0; i < n; ++i) {
    const double c = cos_table_[i];
    const double s = sin_table_[i];
    const double va = d.amplitude_v * s;
    const double vb = d.amplitude_v * (s * cos_phase_ + c * sin_phase_);
    const double q = h.offset_m + h.cos_m * c + h.sin_m * s;
    const double x1 = e[1].group_a * va * va + e[1].group_b * vb * vb;
    const double x2 = e[2].group_a * va + e[2].group_b * vb;
    const double x3 = e[3].group_a * va * va + e[3].group_b * vb * vb;
    const double x4 = e[4].group_a * va + e[4].group_b * vb;
    const double df[4] = {-mode.quadratic_shape * q * q, -mode.cubic_shape * q * q * q, x1 + x2 * q,
                          x3 * q + x4 * q * q};
    for (int p = 0; p < 4; ++p) {
      dr(0, p) -= df[p];
      dr(1, p) -= 2.0 * df[p] * c;
      dr(2, p) -= 2.0 * df[p] * s;
    }
  }
  dr *= inv_n * r_scale;
  Eigen::Matrix3d jm;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) jm(i, k) = jacobian[i][k];
  const Eigen::Matrix<double, 3, 4> dx = jm.partialPivLu().solve(-dr);  // um per unit p
  const double amplitude_um = h.amplitude_m() * kMicro;
  for (int p = 0; p < 4; ++p) {
    branch.tip_amplitude_sensitivity_um[p] =
        amplitude_um > 0.0 ? mode.tip_lever * (h.cos_m * kMicro * dx(1, p) + h.sin_m * kMicro * dx(2, p)) / amplitude_um
                           : 0.0;
  }
}

ModeResponse FreeStatorHarmonicBalance::solve_mode(StatorMode which, double amplitude_v, double frequency_hz,
                                                   std::span<const ModeHarmonics> extra) const {
  ModeResponse response;
  auto add = [&](const ModeHarmonics& seed) {
    ModeBranch branch;
    if (!polish(which, amplitude_v, frequency_hz, seed, branch)) return;
    for (const ModeBranch& b : response.branches) {
      if (same_solution(b.harmonics, branch.harmonics)) return;
    }
    response.branches.push_back(branch);
  };
  for (const ModeHarmonics& seed : closed_form_seeds(which, amplitude_v, frequency_hz)) add(seed);
  for (const ModeHarmonics& seed : extra) add(seed);
  std::sort(response.branches.begin(), response.branches.end(),
            [](const ModeBranch& x, const ModeBranch& y) { return x.tip_amplitude_um > y.tip_amplitude_um; });
  return response;
}

StatorResponse FreeStatorHarmonicBalance::solve(double amplitude_v, double frequency_hz) const {
  StatorResponse r;
  r.amplitude_v = amplitude_v;
  r.frequency_hz = frequency_hz;
  r.normal = solve_mode(StatorMode::l1, amplitude_v, frequency_hz);
  r.tangential = solve_mode(StatorMode::b2, amplitude_v, frequency_hz);
  return r;
}

void FreeStatorHarmonicBalance::peak(StatorMode which, double amplitude_v, double& peak_hz, double& peak_um) const {
  const Mode& mode = mode_data(which);
  const ModeForceCoefficients& m = mode.force;
  const double v0 = amplitude_per_volt_ * amplitude_v;
  const double mass = mode.mass_kg;
  const double c = mode.damping_n_s_m;
  // Closed-form estimate (§6.3): the peak of A(w) has D + k3 A^2 = C^2/(2M).
  const double f_cos = v0 * m.lin0_b * sin_phase_;
  const double f_sin = v0 * (m.lin0_a + m.lin0_b * cos_phase_);
  const double f_dc = 0.5 * (m.sq0_a + m.sq0_b) * v0 * v0;
  const double k_eff = m.k - 0.5 * (m.sq1_a + m.sq1_b) * v0 * v0;
  const double k_first = k_eff + 2.0 * m.k2 * f_dc / k_eff;
  const double k3_eff = 0.75 * m.k3 - m.k2 * m.k2 / k_eff;
  const double force2 = f_cos * f_cos + f_sin * f_sin;
  double w2 = k_first / mass;
  for (int i = 0; i < 50; ++i) {
    const double x = force2 / (c * c * c * c / (4.0 * mass * mass) + c * c * w2);
    const double next = std::max((k_first + k3_eff * x - c * c / (2.0 * mass)) / mass, 1e-6 * w2);
    if (std::abs(next - w2) < 1e-14 * w2) break;
    w2 = next;
  }
  const double f_estimate = std::sqrt(w2) / (2.0 * std::numbers::pi);
  auto amplitude = [&](double f) {
    const ModeResponse r = solve_mode(which, amplitude_v, f);
    return r.branches.empty() ? -1.0 : r.branches.front().tip_amplitude_um;
  };
  // Golden-section search for the maximum of the largest branch (unimodal near the peak).
  const double half_width = 0.1 * c / (2.0 * std::numbers::pi * mass);  // 0.1 bandwidth
  double lo = f_estimate - half_width;
  double hi = f_estimate + half_width;
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = hi - g * (hi - lo);
  double x2 = lo + g * (hi - lo);
  double a1 = amplitude(x1);
  double a2 = amplitude(x2);
  for (int i = 0; i < 40 && hi - lo > 1e-4; ++i) {
    if (a1 < a2) {
      lo = x1;
      x1 = x2;
      a1 = a2;
      x2 = lo + g * (hi - lo);
      a2 = amplitude(x2);
    } else {
      hi = x2;
      x2 = x1;
      a2 = a1;
      x1 = hi - g * (hi - lo);
      a1 = amplitude(x1);
    }
  }
  peak_hz = a1 > a2 ? x1 : x2;
  peak_um = std::max(a1, a2);
}

BackbonePoint FreeStatorHarmonicBalance::backbone(double amplitude_v) const {
  BackbonePoint p;
  p.amplitude_v = amplitude_v;
  peak(StatorMode::l1, amplitude_v, p.normal_peak_hz, p.normal_peak_um);
  peak(StatorMode::b2, amplitude_v, p.tangential_peak_hz, p.tangential_peak_um);
  return p;
}

namespace {

// Index of the branch a quasi-static sweep follows: the stable branch nearest to the
// previously followed state (or the smallest stable one at the first point).
int follow(const ModeResponse& r, const ModeHarmonics* previous) {
  int best = -1;
  double best_score = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < r.branches.size(); ++i) {
    const ModeBranch& b = r.branches[i];
    if (!b.stable) continue;
    const double score = previous != nullptr ? distance(b.harmonics, *previous) : b.tip_amplitude_um;
    if (score < best_score) {
      best_score = score;
      best = static_cast<int>(i);
    }
  }
  return best;
}

template <typename Solve>
std::vector<SweepPoint> sweep(std::size_t count, Solve&& solve_at) {
  std::vector<SweepPoint> out;
  out.reserve(count);
  std::vector<ModeHarmonics> seeds[2];
  ModeHarmonics followed[2];
  bool has_followed[2] = {false, false};
  for (std::size_t i = 0; i < count; ++i) {
    SweepPoint point;
    for (int m = 0; m < 2; ++m) {
      const StatorMode mode = static_cast<StatorMode>(m);
      ModeResponse r = solve_at(i, mode, std::span<const ModeHarmonics>(seeds[m]));
      const int index = follow(r, has_followed[m] ? &followed[m] : nullptr);
      seeds[m].clear();
      for (const ModeBranch& b : r.branches) seeds[m].push_back(b.harmonics);
      if (index >= 0) {
        followed[m] = r.branches[index].harmonics;
        has_followed[m] = true;
      }
      (m == 0 ? point.followed_normal : point.followed_tangential) = index;
      (m == 0 ? point.response.normal : point.response.tangential) = std::move(r);
    }
    out.push_back(std::move(point));
  }
  return out;
}

}  // namespace

std::vector<SweepPoint> sweep_frequency(const FreeStatorHarmonicBalance& hb, double amplitude_v,
                                        std::span<const double> frequencies_hz) {
  auto points = sweep(frequencies_hz.size(), [&](std::size_t i, StatorMode mode, std::span<const ModeHarmonics> seeds) {
    return hb.solve_mode(mode, amplitude_v, frequencies_hz[i], seeds);
  });
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i].response.amplitude_v = amplitude_v;
    points[i].response.frequency_hz = frequencies_hz[i];
  }
  return points;
}

std::vector<SweepPoint> sweep_voltage(const FreeStatorHarmonicBalance& hb, double frequency_hz,
                                      std::span<const double> amplitudes_v) {
  auto points = sweep(amplitudes_v.size(), [&](std::size_t i, StatorMode mode, std::span<const ModeHarmonics> seeds) {
    return hb.solve_mode(mode, amplitudes_v[i], frequency_hz, seeds);
  });
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i].response.amplitude_v = amplitudes_v[i];
    points[i].response.frequency_hz = frequency_hz;
  }
  return points;
}

}  // namespace swum
