// Time-domain integration of the free stator (mover removed, eqs. 26-27: eqs. 14-15 without
// F_N and F_T) with the library's Dormand-Prince reference integrator. The independent check
// of the harmonic balance (docs/harmonic_balance.md, "Verification").
#pragma once

#include <array>

#include "model/machine/stator.h"
#include "model/modal/modal_constants.h"
#include "model/parameters.h"

namespace swum {

// State [q1, q1', q2, q2'] (m, m/s); V_A = V0 sin(wt), V_B = V0 sin(wt + phase).
struct FreeStatorOde {
  using Vector = std::array<double, 4>;
  StatorForceCoefficients force;
  double m1_kg = 0.0, c1_n_s_m = 0.0, m2_kg = 0.0, c2_n_s_m = 0.0;
  double amplitude_v = 0.0;
  double omega_rad_s = 0.0;
  double cos_phase = 0.0, sin_phase = 1.0;

  void derivative(double t, const Vector& x, Vector& dx) const;
};

struct FreeStatorRunOptions {
  double settle_s = 0.010;  // discarded (several modal time constants 2M/C ~ 1-1.5 ms)
  double window_s = 0.002;  // amplitudes = (max - min)/2 over this window
  double relative_tolerance = 1e-10;
  double samples_per_cycle = 200.0;  // max step 1/(this f): resolves the extrema
  double phase_deg = 90.0;
};

struct FreeStatorAmplitudes {
  bool ok = false;
  double tip_normal_um = 0.0;      // (max - min)/2 of |phiL(L)| q1
  double tip_tangential_um = 0.0;  // (max - min)/2 of phiB(L) q2 (eq. 30)
  double mean_q1_m = 0.0;          // mean over the window (DC offset)
  double mean_q2_m = 0.0;
};

// Integrates from `initial` (t = 0) and measures the last window.
[[nodiscard]] FreeStatorAmplitudes simulate_free_stator(const ModalConstants& constants, const StatorParameters& stator,
                                                        double amplitude_v, double frequency_hz,
                                                        const std::array<double, 4>& initial,
                                                        const FreeStatorRunOptions& options = {});

}  // namespace swum
