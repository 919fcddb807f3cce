// Composition of stator (eqs. 14-15), interface (16, 21-22) and mover (23-25) into the
// complete state-space model of model_spec §4, in the two forms the integrators need:
//  * MotorSplitSystem: explicit smooth accelerations + implicit friction velocity correction
//    (semi-implicit Euler, §10);
//  * MotorOde: the full first-order system with the erf friction law (reference solver).
#pragma once

#include <array>
#include <cmath>
#include <functional>

#include "model/machine/contact.h"
#include "model/machine/drive.h"
#include "model/machine/mover.h"
#include "model/machine/stator.h"
#include "model/motor_model.h"

namespace swum {

// Interface forces of the last evaluation (N). friction_n acts on the mover (+y);
// the stator receives -gT friction_n (§1.4 reading).
struct InterfaceForces {
  double normal_n = 0.0;
  double friction_n = 0.0;
  double guide_n = 0.0;
};

// Positions (q1, q2, x_m), velocities (q1', q2', v_m); the Jenkins deflection delta is an
// internal variable of the system (updated by a return mapping at the end of each step).
class MotorSplitSystem {
 public:
  using Vector = std::array<double, 3>;

  // Holds a copy of the coefficients (no aliasing with the state in the hot loop). The modal
  // inverse masses are step-corrected for time_step_s (see update_step).
  MotorSplitSystem(const MotorCoefficients& coefficients, double time_step_s)
      : k_(coefficients), paired_(make_paired_force_coefficients(coefficients.stator)) {
    update_step(time_step_s);
  }

  void set_inputs(const DriveVoltages& voltages, double load_n) {
    voltages_ = voltages;
    load_n_ = load_n;
  }

  // Smooth forces at (q, v): stator modal forces, damping, contact F_N (and the constant
  // back-end preload), load and mover damping.
  void explicit_acceleration(double /*t*/, const Vector& q, const Vector& v, Vector& a) {
    const double fn = normal_force_n(k_.preload_n, k_.contact_stiffness_n_m, q[0]);
    forces_.normal_n = fn;
    const DoublePair f = modal_forces_n(paired_, DoublePair{q[0], q[1]}, voltages_.va_v, voltages_.vb_v);
    a[0] = a1_per_kg_ * (f[0] + k_.g_n * fn + k_.preload_constant_force_n - k_.c1_n_s_m * v[0]);
    a[1] = a2_per_kg_ * (f[1] - k_.c2_n_s_m * v[1]);
    a[2] = k_.mover_mass_inv_per_kg * (-load_n_ - k_.mover_damping_n_s_m * v[2]);
  }

  // Runtime dispatch to the specialised correction (the simulator's hot loop calls the
  // specialisation directly).
  void implicit_velocity_correction(double t, double dt, const Vector& q, const Vector& v, Vector& v_star) {
    dispatch(
        [&]<TangentialContact C, GuideFrictionModel G>() { implicit_velocity_correction<C, G>(t, dt, q, v, v_star); });
  }

  // Tangential contact (implicit friction, §10 steps 3-4, or the explicit Jenkins spring),
  // guide friction, and for the Jenkins element the return mapping of delta with the
  // positions of the end of the step. kMoverHeld (a jammed mover, model_faults.h): the mover
  // is fixed (v_m = 0 in and out, infinite mass in the contact compliance), the stator tip
  // rubs on it and there is no guide force.
  template <TangentialContact C, GuideFrictionModel G, bool kMoverHeld = false>
  void implicit_velocity_correction(double /*t*/, double dt, const Vector& q, const Vector& v, Vector& v_star) {
    if (dt != cached_dt_) [[unlikely]]
      update_step(dt);
    if constexpr (kMoverHeld) v_star[2] = 0.0;
    const double fn = forces_.normal_n;
    const double limit = k_.friction_coefficient * fn;
    double ft = 0.0;
    if constexpr (C == TangentialContact::jenkins) {
      // A deflection outside the cone (after set_contact_deflection_m, a lower preload or mu_c)
      // is projected onto it: the spring cannot hold more than the slider transmits. Inside it
      // (always, after a return mapping with the same F_N) this changes nothing.
      const double cone_m = k_.slider_limit_per_normal_force_m_n * fn;
      deflection_m_ = deflection_m_ > cone_m ? cone_m : (deflection_m_ < -cone_m ? -cone_m : deflection_m_);
      ft = jenkins_force_n(k_.tangential_stiffness_n_m, deflection_m_, limit);
    } else if constexpr (C == TangentialContact::rigid_projection) {
      // Coulomb projection, written with the precomputed inverse compliance.
      const double f = (k_.g_tv * v_star[1] - v_star[2]) *
                       (kMoverHeld ? inverse_held_compliance_ : inverse_compliance_);
      ft = f > limit ? limit : (f < -limit ? -limit : f);
    } else {
      if (limit > 0.0) {
        ft = erf_implicit_friction_n(k_.g_tv * v_star[1] - v_star[2], kMoverHeld ? held_compliance_ : compliance_,
                                     limit, k_.kappa_s_per_m);
      }
    }
    v_star[1] -= dt_g_t_over_m2_ * ft;
    double ff = 0.0;
    if constexpr (kMoverHeld) {
      // The hard stop takes the friction and the load; the mover stays where it is.
    } else if constexpr (G == GuideFrictionModel::implicit_coulomb) {
      const double v_pred = v_star[2] + dt_over_m_ * ft;
      const double cap = dt_mu_s_over_m_ * (fn + k_.guide.weight_n);
      v_star[2] = coulomb_guide_velocity_m_s(v_pred, cap);
      ff = (v_star[2] - v_pred) * m_over_dt_;
    } else {
      ff = guide_friction_n(k_.guide, ft, fn, load_n_, v[2]);
      v_star[2] += dt_over_m_ * (ft + ff);
    }
    forces_.friction_n = ft;
    forces_.guide_n = ff;
    if constexpr (C == TangentialContact::jenkins) {
      const double q1_next = q[0] + dt * v_star[0];
      const double fn_next = normal_force_n(k_.preload_n, k_.contact_stiffness_n_m, q1_next);
      deflection_m_ = jenkins_return_mapping_m(deflection_m_, dt * (k_.g_tv * v_star[1] - v_star[2]),
                                               k_.slider_limit_per_normal_force_m_n * fn_next);
    }
  }

  // Calls f.template operator()<C, G>() for the configured contact law and guide model.
  template <typename F>
  void dispatch(F&& f) const {
    const auto guide = k_.guide_model;
    switch (k_.tangential) {
      case TangentialContact::jenkins:
        return guide == GuideFrictionModel::implicit_coulomb
                   ? f.template operator()<TangentialContact::jenkins, GuideFrictionModel::implicit_coulomb>()
                   : f.template operator()<TangentialContact::jenkins, GuideFrictionModel::smoothed_sign>();
      case TangentialContact::rigid_erf:
        return guide == GuideFrictionModel::implicit_coulomb
                   ? f.template operator()<TangentialContact::rigid_erf, GuideFrictionModel::implicit_coulomb>()
                   : f.template operator()<TangentialContact::rigid_erf, GuideFrictionModel::smoothed_sign>();
      case TangentialContact::rigid_projection: break;
    }
    return guide == GuideFrictionModel::implicit_coulomb
               ? f.template operator()<TangentialContact::rigid_projection, GuideFrictionModel::implicit_coulomb>()
               : f.template operator()<TangentialContact::rigid_projection, GuideFrictionModel::smoothed_sign>();
  }

  // Slow effects (effects.h), called by the simulator's housekeeping, never per step:
  // modal stiffness and damping scaled from `base` (thermal) and the friction coefficient (wear).
  void set_modal_factors(const MotorCoefficients& base, double stiffness_factor, double damping_factor) {
    k_.stator.l1.k = base.stator.l1.k * stiffness_factor;
    k_.stator.b2.k = base.stator.b2.k * stiffness_factor;
    paired_.k = DoublePair{k_.stator.l1.k, k_.stator.b2.k};
    k_.c1_n_s_m = base.c1_n_s_m * damping_factor;
    k_.c2_n_s_m = base.c2_n_s_m * damping_factor;
    update_step(cached_dt_);
  }
  // Run-time faults (model_faults.h), set between steps: F_P (both the contact's and the constant
  // back-end term) and mu_s of the guide scaled from `base`. A factor of 1 restores base exactly.
  void set_preload_factor(const MotorCoefficients& base, double factor) {
    k_.preload_n = base.preload_n * factor;
    k_.preload_constant_force_n = base.preload_constant_force_n * factor;
  }
  void set_guide_friction_factor(const MotorCoefficients& base, double factor) {
    k_.guide.coefficient = base.guide.coefficient * factor;
    dt_mu_s_over_m_ = dt_over_m_ * k_.guide.coefficient;
  }
  void set_friction_coefficient(double friction_coefficient) {
    k_.friction_coefficient = friction_coefficient;
    if (k_.tangential_stiffness_n_m > 0.0) {
      k_.slider_limit_per_normal_force_m_n = friction_coefficient / k_.tangential_stiffness_n_m;
    }
  }
  [[nodiscard]] double damping_power_w(const Vector& v) const {
    return k_.c1_n_s_m * v[0] * v[0] + k_.c2_n_s_m * v[1] * v[1];
  }
  // Cycle mean of damping_power_w from one sample of a steady vibration at w: for
  // z = A sin(wt), v = A w cos(wt), C v^2 averages to C A^2 w^2 / 2 = C (v^2 + w^2 z^2) / 2,
  // whatever the phase of the sample (z: modal displacements about their static values).
  [[nodiscard]] double mean_damping_power_w(double z1, double z2, const Vector& v,
                                            double angular_frequency_rad_s) const {
    const double w2 = angular_frequency_rad_s * angular_frequency_rad_s;
    return 0.5 * (k_.c1_n_s_m * (v[0] * v[0] + w2 * z1 * z1) + k_.c2_n_s_m * (v[1] * v[1] + w2 * z2 * z2));
  }

  // The step-dependent constants of update_step, for a solver that runs the same step on
  // other data (BatchSimulator: the same model in SIMD lanes).
  struct StepConstants {
    double a1_per_kg, a2_per_kg, inverse_compliance, dt_g_t_over_m2, dt_over_m, m_over_dt, dt_mu_s_over_m;
  };
  [[nodiscard]] const MotorCoefficients& coefficients() const { return k_; }
  [[nodiscard]] StepConstants step_constants() const {
    return {a1_per_kg_, a2_per_kg_, inverse_compliance_, dt_g_t_over_m2_, dt_over_m_, m_over_dt_, dt_mu_s_over_m_};
  }

  [[nodiscard]] const InterfaceForces& forces() const { return forces_; }
  // The last step's forces, for a solver that runs this system's step on its own copy of the
  // state (MotorSimulator's fused Jenkins loop).
  void set_forces(const InterfaceForces& forces) { forces_ = forces; }
  // The stator's modal force coefficients as the hot loop uses them (electrical.h derives the
  // phase currents from the same numbers).
  [[nodiscard]] const PairedForceCoefficients& paired_coefficients() const { return paired_; }
  [[nodiscard]] double contact_deflection_m() const { return deflection_m_; }
  void set_contact_deflection_m(double deflection_m) {
    deflection_m_ = k_.tangential == TangentialContact::jenkins ? deflection_m : 0.0;
  }

 private:
  // Step-dependent constants. The modal updates are
  //   v_n+1 = v_n + dt s_i/M_i (f - C_i (v_n + v_n+1)/2) / ...  =  v_n + dt A_i (f - C_i v_n),
  //   A_i = (s_i/M_i) / (1 + dt C_i s_i/(2 M_i)),  s_i = (sin(theta_i/2)/(theta_i/2))^2,
  //   theta_i = w_i dt (w_i = sqrt(K_i/M_i)):
  // centred (trapezoidal, implicit) modal damping instead of the lagged C v_n-1/2 of plain
  // symplectic Euler (whose lag acts as an extra stiffness C w^2 dt/2), and the inertia
  // corrected for the leapfrog dispersion (4/dt^2 sin^2(w dt/2) instead of w^2), so that the
  // discrete oscillator has the exact resonance and damping. Both errors are O(dt) relative
  // to the bandwidth and shift the resonance up by ~(theta/2 + Q theta^2/12) half-bandwidths.
  // The interface impulses on q2 use the same A_2 (implicit in the damping).
  void update_step(double dt) {
    cached_dt_ = dt;
    auto corrected = [dt](double m_inv, double k, double c) {
      const double half_theta = 0.5 * std::sqrt(k * m_inv) * dt;
      const double s = half_theta > 0.0 ? std::pow(std::sin(half_theta) / half_theta, 2) : 1.0;
      return s * m_inv / (1.0 + 0.5 * dt * c * s * m_inv);
    };
    a1_per_kg_ = corrected(k_.m1_inv_per_kg, k_.stator.l1.k, k_.c1_n_s_m);
    a2_per_kg_ = corrected(k_.m2_inv_per_kg, k_.stator.b2.k, k_.c2_n_s_m);
    compliance_ = dt * (k_.g_t * k_.g_tv * a2_per_kg_ + k_.mover_mass_inv_per_kg);
    inverse_compliance_ = 1.0 / compliance_;
    held_compliance_ = dt * k_.g_t * k_.g_tv * a2_per_kg_;  // mover held: the stator's share only
    inverse_held_compliance_ = 1.0 / held_compliance_;
    dt_g_t_over_m2_ = dt * k_.g_t * a2_per_kg_;
    dt_over_m_ = dt * k_.mover_mass_inv_per_kg;
    m_over_dt_ = 1.0 / dt_over_m_;
    dt_mu_s_over_m_ = dt_over_m_ * k_.guide.coefficient;
  }

  MotorCoefficients k_;
  PairedForceCoefficients paired_;
  double cached_dt_ = 0.0;
  double a1_per_kg_ = 0.0;  // A_1, A_2 of update_step
  double a2_per_kg_ = 0.0;
  double compliance_ = 0.0;
  double inverse_compliance_ = 0.0;
  double held_compliance_ = 0.0;
  double inverse_held_compliance_ = 0.0;
  double dt_g_t_over_m2_ = 0.0;
  double dt_over_m_ = 0.0;
  double m_over_dt_ = 0.0;
  double dt_mu_s_over_m_ = 0.0;
  double deflection_m_ = 0.0;
  DriveVoltages voltages_{};
  double load_n_ = 0.0;
  InterfaceForces forces_{};
};

// The system with the contact law and guide model (and a held mover, kMoverHeld) fixed at
// compile time (no per-step dispatch); satisfies SplitSecondOrderSystem.
template <TangentialContact C, GuideFrictionModel G, bool kMoverHeld = false>
struct SpecialisedMotorSystem {
  using Vector = MotorSplitSystem::Vector;
  MotorSplitSystem& system;
  void explicit_acceleration(double t, const Vector& q, const Vector& v, Vector& a) {
    system.explicit_acceleration(t, q, v, a);
  }
  void implicit_velocity_correction(double t, double dt, const Vector& q, const Vector& v, Vector& v_star) {
    system.template implicit_velocity_correction<C, G, kMoverHeld>(t, dt, q, v, v_star);
  }
};

// x = (q1, q1', q2, q2', x_m, v_m, theta, delta); theta' = 2 pi f(t) keeps the drive phase
// continuous when the frequency changes, exactly as the fixed-step phasor does; delta is the
// Jenkins deflection (play-operator form, jenkins_deflection_rate_m_s; constant 0 if k_t = 0).
// Rigid contact: erf law (kappa = 3.6 * 10^a). Guide: eqs. 24-25 with tanh sign, or for
// implicit_coulomb the regularised Coulomb -mu_s (F_N + g m) tanh(v_m/w).
class MotorOde {
 public:
  using Vector = std::array<double, 8>;
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
