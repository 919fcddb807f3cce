#include "analysis/steady_state/steady_state.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "integrators/dormand_prince.h"
#include "model/machine/motor.h"
#include "model/simulation/simulator.h"

namespace swum {
namespace {

// One window: the statistics of its steps and where the mover started.
struct WindowStats : WindowStatistics {
  double start_position_m = 0.0;
  ElectricalSums electrical;  // fixed-step solver only

  void store(double end_position_m, SteadyStateResult& r) const {
    store_window(*this, duration_s, start_position_m, end_position_m, r);
  }
};

// True when another window would end after max_s: the window that ends at elapsed_s is the last.
bool no_window_after(const SteadyStateOptions& opt, double elapsed_s) {
  return elapsed_s + opt.window_s > opt.max_s + 1e-12;
}

// Shared window logic: `run(duration, stats_or_null)` advances the solver; returns false on
// failure (diverged or solver failure, with result.failure set).
template <typename Run, typename Position>
SteadyStateResult window_loop(const SteadyStateOptions& opt, Run&& run, Position&& position) {
  SteadyStateResult r;
  if (!run(opt.settle_s, nullptr, r)) return r;
  double previous_speed = std::numeric_limits<double>::quiet_NaN();
  double elapsed = opt.settle_s;
  while (true) {
    WindowStats w;
    w.start_position_m = position();
    // Running to max_s (stop_when_settled false), only the last window's statistics are reported
    // and the verdict compares speeds: the windows before it run without statistics, so that a
    // timing run costs what its steps cost (issue 16). Stopping when settled, any window may be
    // the last.
    const bool last = no_window_after(opt, elapsed + opt.window_s);
    const bool statistics = opt.stop_when_settled || last;
    const double start_s = r.sim_s;
    if (!run(opt.window_s, statistics ? &w : nullptr, r)) return r;
    elapsed += opt.window_s;
    if (statistics) {
      w.store(position(), r);
    } else {
      r.speed_mm_s = 1e3 * (position() - w.start_position_m) / (r.sim_s - start_s);
    }
    ++r.windows;
    if (window_verdict(opt, elapsed, previous_speed, r)) return r;
  }
}

}  // namespace

ElectricalReadings window_electrical(const ElectricalSums& sums, const OperatingPoint& point) {
  // No drive, no measurement (as the emulator): a ring-down current has nothing to refer to.
  return point.amplitude_v > 0.0 ? electrical_readings(sums, point.phase_deg) : ElectricalReadings{};
}

void store_window(const WindowStatistics& w, double duration_s, double start_position_m, double end_position_m,
                  SteadyStateResult& r) {
  const double T = duration_s;
  r.speed_mm_s = 1e3 * (end_position_m - start_position_m) / T;
  r.tip_normal_um = 1e6 * 0.5 * (w.u_max_m - w.u_min_m);
  r.tip_tangential_um = 1e6 * 0.5 * (w.w_max_m - w.w_min_m);
  r.contact_fraction = w.contact_s / T;
  r.mean_friction_force_n = w.ft_sum_n_s / T;
  r.mean_normal_force_n = w.fn_sum_n_s / T;
  r.damping_power_w = w.energy_j / T;
  r.slip_power_w = w.slip_energy_j / T;
  r.mover_power_w = w.mover_energy_j / T;
  r.friction_force_std_n = std::sqrt(
      std::max(0.0, w.ft2_sum_n2_s / T - r.mean_friction_force_n * r.mean_friction_force_n));
}

bool window_verdict(const SteadyStateOptions& opt, double elapsed_s, double& previous_speed_mm_s,
                    SteadyStateResult& r) {
  if (!std::isnan(previous_speed_mm_s)) {
    r.speed_change_mm_s = r.speed_mm_s - previous_speed_mm_s;
    const double tolerance = std::max(opt.speed_tolerance_mm_s, opt.speed_relative_tolerance * std::abs(r.speed_mm_s));
    r.ok = std::abs(r.speed_change_mm_s) <= tolerance;
    if (r.ok && opt.stop_when_settled) return true;
  }
  previous_speed_mm_s = r.speed_mm_s;
  if (no_window_after(opt, elapsed_s)) {
    if (r.ok) return true;  // ran on after settling (stop_when_settled false): the last two agree
    r.failure = r.windows < 2 ? std::string("only one window fits within ") + std::to_string(opt.max_s) +
                                    " s: nothing to compare it with"
                              : std::string("did not settle within ") + std::to_string(opt.max_s) +
                                    " s: last two windows differ by " + std::to_string(r.speed_change_mm_s) + " mm/s";
    return true;
  }
  return false;
}

std::string diverged_failure(double time_s) {
  return std::string("diverged (non-finite or runaway state) at t = ") + std::to_string(time_s) + " s";
}

SteadyStateOptions steady_state_options_within(double duration_s) {
  SteadyStateOptions options;
  options.window_s = std::min(options.window_s, duration_s / 2.0);
  options.settle_s = std::clamp(duration_s - 2.0 * options.window_s, 0.0, options.settle_s);
  options.max_s = duration_s;
  return options;
}

SteadyStateResult run_to_steady_state(const MotorModel& model, const OperatingPoint& point,
                                      const SteadyStateOptions& opt) {
  MotorSimulator sim(model);
  DriveInput drive;
  drive.amplitude_v = point.amplitude_v;
  drive.frequency_hz = point.frequency_hz;
  drive.phase_deg = point.phase_deg;
  drive.load_n = point.load_n;
  sim.set_drive(drive);
  if (point.initial_state) sim.set_state(*point.initial_state);
  sim.set_slow_states(point.stator_temperature_rise_k, point.sliding_distance_m, point.freeze_slow_states);
  const double dt = sim.time_step_s();
  const double g_tv = model.coefficients().g_tv;
  const double damping_factor = thermal_factors(model.coefficients().effects, point.stator_temperature_rise_k).damping;
  const double c1 = model.coefficients().c1_n_s_m * damping_factor;
  const double c2 = model.coefficients().c2_n_s_m * damping_factor;
  std::uint64_t total_steps = 0;

  const bool traced = opt.trace && opt.trace_every_steps > 0;
  auto run = [&](double duration_s, WindowStats* w, SteadyStateResult& r) {
    const auto steps = static_cast<std::uint64_t>(std::llround(duration_s / dt));
    if (w != nullptr) {
      w->c1_n_s_m = c1;
      w->c2_n_s_m = c2;
    }
    if (!traced) {
      // The hot loop, the window statistics inside it: nothing per step through a call.
      if (w != nullptr) sim.advance(steps, *w, w->electrical);
      else sim.advance(steps);
      total_steps += steps;
    }
    for (std::uint64_t k = 0; traced && k < steps;) {
      // The hot loop up to the next trace sample (the window sums inside it are the same bits
      // as step() and window.add() one step at a time; tests/src/model/simulation/simulator_test.cpp).
      const std::uint64_t chunk = std::min(steps - k, opt.trace_every_steps - total_steps % opt.trace_every_steps);
      if (w != nullptr) sim.advance(chunk, *w, w->electrical);
      else sim.advance(chunk);
      k += chunk;
      total_steps += chunk;
      const auto& s = sim.state();
      const auto& f = sim.forces();
      if (total_steps % opt.trace_every_steps == 0) {
        opt.trace(TraceSample{s.time_s, s.q1_m, s.q1_dot_m_s, s.q2_m, s.q2_dot_m_s, -1e6 * s.q1_m, 1e6 * g_tv * s.q2_m,
                              f.normal_n, f.friction_n, s.mover_position_m, s.mover_velocity_m_s});
      }
    }
    r.steps = total_steps;
    r.sim_s = sim.state().time_s;
    if (w != nullptr) r.electrical = window_electrical(w->electrical, point);
    if (sim.diverged()) {
      r.diverged = true;
      r.ok = false;
      r.failure = diverged_failure(sim.state().time_s);
      return false;
    }
    return true;
  };
  SteadyStateResult result = window_loop(opt, run, [&] { return sim.state().mover_position_m; });
  result.final_state = sim.state();
  return result;
}

SteadyStateResult run_to_steady_state_reference(const MotorModel& model, const OperatingPoint& point,
                                                const SteadyStateOptions& opt) {
  DriveInput drive;
  drive.amplitude_v = point.amplitude_v;
  drive.frequency_hz = point.frequency_hz;
  drive.phase_deg = point.phase_deg;
  drive.load_n = point.load_n;
  const MotorOde ode(model, [drive](double) { return drive; });
  MotorOde::Vector x = MotorOde::pack(model.rest_state(), 0.0);
  DormandPrinceOptions<MotorOde::Vector> dp;
  dp.relative_tolerance = opt.reference_relative_tolerance;
  dp.absolute_tolerance = {1e-15, 1e-10, 1e-15, 1e-10, 1e-13, 1e-10, 1e-10, 1e-16};
  dp.max_step = 1.0 / (opt.reference_samples_per_cycle * std::max(point.frequency_hz, 1.0));
  dp.initial_step = 1e-9;
  const double g_tv = model.coefficients().g_tv;
  const double speed_limit = model.parameters().numerics.divergence_speed_limit_m_s;
  const double position_limit = model.parameters().numerics.divergence_limit_um * 1e-6;
  double t = 0.0;
  std::uint64_t accepted = 0;

  auto run = [&](double duration_s, WindowStats* w, SteadyStateResult& r) {
    double t_prev = t;
    const auto observer = [&](double tn, const MotorOde::Vector& xn) {
      ++accepted;
      const InterfaceForces f = ode.forces(tn, xn);
      if (w != nullptr) w->add(tn - t_prev, -xn[0], g_tv * xn[2], f.normal_n, f.friction_n, 0.0);
      t_prev = tn;
      if (opt.trace && opt.trace_every_steps > 0 && accepted % opt.trace_every_steps == 0) {
        opt.trace(TraceSample{tn, xn[0], xn[1], xn[2], xn[3], -1e6 * xn[0], 1e6 * g_tv * xn[2], f.normal_n,
                              f.friction_n, xn[4], xn[5]});
      }
    };
    const auto stats = integrate_dormand_prince(ode, t, t + duration_s, x, dp, observer);
    if (stats.last_step > 0.0) dp.initial_step = stats.last_step;
    t += duration_s;
    r.steps = accepted;
    r.sim_s = t;
    const bool sane = std::abs(x[0]) < position_limit && std::abs(x[2]) < position_limit &&
                      std::abs(x[5]) < speed_limit;
    if (!stats.ok || !sane) {
      r.diverged = !sane;
      r.ok = false;
      r.failure = !sane ? "diverged (non-finite or runaway state)"
                        : "reference solver failed (step size underflow or step limit)";
      return false;
    }
    return true;
  };
  return window_loop(opt, run, [&] { return x[4]; });
}

}  // namespace swum
