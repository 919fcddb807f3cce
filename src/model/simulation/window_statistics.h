// Time-weighted statistics of a run of fixed steps (a steady-state window, model_spec §10):
// tip displacement extremes, contact time, friction, normal force and damping power. Filled
// inside the simulator's hot loop (MotorSimulator::advance(steps, stats)) so that a window
// costs what its steps cost; also filled step by step by the reference solver.
#pragma once

#include <algorithm>
#include <limits>

namespace swum {

struct WindowStatistics {
  // Modal damping coefficients (N s/m) weighting the power C1 q1'^2 + C2 q2'^2; the caller
  // sets them (they follow the thermal effect's damping factor).
  double c1_n_s_m = 0.0;
  double c2_n_s_m = 0.0;

  double duration_s = 0.0;
  double u_min_m = std::numeric_limits<double>::infinity();  // u_tip = -q1
  double u_max_m = -std::numeric_limits<double>::infinity();
  double w_min_m = std::numeric_limits<double>::infinity();  // w_tip = gTv q2
  double w_max_m = -std::numeric_limits<double>::infinity();
  double contact_s = 0.0;  // time with F_N > 0
  double ft_sum_n_s = 0.0, ft2_sum_n2_s = 0.0, fn_sum_n_s = 0.0, energy_j = 0.0;
  // The power balance at the interface (docs/model.md "Electrical port"): the work the B2 mode
  // gives the contact through -gT F_T less what reaches the mover, F_T (gT q2' - v_m) (slip in
  // the contact, plus the Jenkins element's stored energy, whose mean is zero), and what reaches
  // the mover, F_T v_m (load, mover damping, guide friction, kinetic energy). End-of-step
  // velocities, as the step's work.
  double slip_energy_j = 0.0, mover_energy_j = 0.0;

  void add(double dt, double u, double w, double fn, double ft, double power_w) {
    energy_j += dt * power_w;
    duration_s += dt;
    u_min_m = std::min(u_min_m, u);
    u_max_m = std::max(u_max_m, u);
    w_min_m = std::min(w_min_m, w);
    w_max_m = std::max(w_max_m, w);
    if (fn > 0.0) contact_s += dt;
    ft_sum_n_s += dt * ft;
    ft2_sum_n2_s += dt * ft * ft;
    fn_sum_n_s += dt * fn;
  }
  // tip_velocity_m_s = gT q2' (the lever of the force on B2), mover_velocity_m_s = v_m.
  void add_interface(double dt, double ft, double tip_velocity_m_s, double mover_velocity_m_s) {
    const double impulse = dt * ft;
    slip_energy_j += impulse * (tip_velocity_m_s - mover_velocity_m_s);
    mover_energy_j += impulse * mover_velocity_m_s;
  }
  // The power the fixed-step path adds, from the modal velocities (m/s).
  [[nodiscard]] double damping_power_w(double q1_dot_m_s, double q2_dot_m_s) const {
    return c1_n_s_m * q1_dot_m_s * q1_dot_m_s + c2_n_s_m * q2_dot_m_s * q2_dot_m_s;
  }
};

}  // namespace swum
