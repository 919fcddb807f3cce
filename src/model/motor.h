// Composition of stator (eqs. 14-15), interface (16, 21-22) and mover (23-25) into the
// complete state-space model of MODEL_SPEC §4, in the two forms the integrators need:
//  * MotorSplitSystem: explicit smooth accelerations + implicit friction velocity correction
//    (semi-implicit Euler, §10);
//  * MotorOde: the full first-order system with the erf friction law (reference solver).
#pragma once

#include <array>
#include <functional>

#include "model/contact.h"
#include "model/drive.h"
#include "model/motor_model.h"
#include "model/mover.h"
#include "model/stator.h"

namespace swum {

// Interface forces of the last evaluation (N). friction_n acts on the mover (+y);
// the stator receives -gT friction_n (§1.4 reading).
struct InterfaceForces {
  double normal_n = 0.0;
  double friction_n = 0.0;
  double guide_n = 0.0;
};

// Positions (q1, q2, x_m), velocities (q1', q2', v_m).
class MotorSplitSystem {
 public:
  using Vector = std::array<double, 3>;

  // Holds a copy of the coefficients (no aliasing with the state in the hot loop).
  MotorSplitSystem(const MotorCoefficients& coefficients, FrictionSolver solver)
      : k_(coefficients),
        paired_(make_paired_force_coefficients(coefficients.stator)),
        solver_(solver) {}

  void set_inputs(const DriveVoltages& voltages, double load_n) {
    voltages_ = voltages;
    load_n_ = load_n;
  }

  // Smooth forces at (q, v): stator modal forces, damping, contact F_N, load and mover damping.
  void explicit_acceleration(double /*t*/, const Vector& q, const Vector& v, Vector& a) {
    const double fn = normal_force_n(k_.preload_n, k_.contact_stiffness_n_m, q[0]);
    forces_.normal_n = fn;
    const DoublePair f = modal_forces_n(paired_, DoublePair{q[0], q[1]}, voltages_.va_v,
                                        voltages_.vb_v);
    a[0] = k_.m1_inv_per_kg * (f[0] + k_.g_n * fn - k_.c1_n_s_m * v[0]);
    a[1] = k_.m2_inv_per_kg * (f[1] - k_.c2_n_s_m * v[1]);
    a[2] = k_.mover_mass_inv_per_kg * (-load_n_ - k_.mover_damping_n_s_m * v[2]);
  }

  // Friction (implicit, §10 steps 3-4) and guide friction (eqs. 24-25, with v_m of step start).
  void implicit_velocity_correction(double /*t*/, double dt, const Vector& /*q*/,
                                    const Vector& v, Vector& v_star) {
    const double limit = k_.friction_coefficient * forces_.normal_n;
    if (dt != cached_dt_) [[unlikely]] {
      cached_dt_ = dt;
      compliance_ = dt * (k_.g_t * k_.g_tv * k_.m2_inv_per_kg + k_.mover_mass_inv_per_kg);
      inverse_compliance_ = 1.0 / compliance_;
    }
    double ft = 0.0;
    const double v_rel = k_.g_tv * v_star[1] - v_star[2];
    if (solver_ == FrictionSolver::coulomb_projection) {
      // Coulomb projection, written with the precomputed inverse compliance.
      const double f = v_rel * inverse_compliance_;
      ft = f > limit ? limit : (f < -limit ? -limit : f);
    } else if (limit > 0.0) {
      ft = erf_implicit_friction_n(v_rel, compliance_, limit, k_.kappa_s_per_m);
    }
    const double ff = guide_friction_n(k_.guide, ft, forces_.normal_n, load_n_, v[2]);
    forces_.friction_n = ft;
    forces_.guide_n = ff;
    v_star[1] -= dt * k_.g_t * ft * k_.m2_inv_per_kg;
    v_star[2] += dt * (ft + ff) * k_.mover_mass_inv_per_kg;
  }

  [[nodiscard]] const InterfaceForces& forces() const { return forces_; }

 private:
  MotorCoefficients k_;
  PairedForceCoefficients paired_;
  FrictionSolver solver_;
  double cached_dt_ = 0.0;
  double compliance_ = 0.0;
  double inverse_compliance_ = 0.0;
  DriveVoltages voltages_{};
  double load_n_ = 0.0;
  InterfaceForces forces_{};
};

// x = (q1, q1', q2, q2', x_m, v_m, theta); theta' = 2 pi f(t) keeps the drive phase continuous
// when the frequency changes, exactly as the fixed-step phasor does.
class MotorOde {
 public:
  using Vector = std::array<double, 7>;
  using DriveSchedule = std::function<DriveInput(double time_s)>;

  MotorOde(const MotorModel& model, DriveSchedule schedule)
      : k_(model.coefficients()), schedule_(std::move(schedule)) {}

  void derivative(double t, const Vector& x, Vector& dxdt) const;

  // Interface forces at (t, x) with the erf law.
  [[nodiscard]] InterfaceForces forces(double t, const Vector& x) const;

  [[nodiscard]] static Vector pack(const MotorState& s, double theta_rad);
  static void unpack(const Vector& x, double t, MotorState& s);

 private:
  const MotorCoefficients& k_;
  DriveSchedule schedule_;
};

}  // namespace swum
