// First-harmonic balance of the free stator (mover removed): paper eqs. (26)-(32), done as
// model_spec §6.2 (alternating-frequency-time, DC + first harmonic per mode) seeded by the
// closed form of §6.3 (every real root of the cubic in A^2). docs/harmonic_balance.md has
// the derivation, the stability criterion and the verification against time-domain runs.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "model/machine/stator.h"
#include "model/modal/modal_constants.h"
#include "model/motor_model.h"
#include "model/parameters.h"

namespace swum {

// The two stator modes; in the free stator (eqs. 26-27) they are independent oscillators.
enum class StatorMode { l1 = 0, b2 = 1 };

// The four non-linear constants of Table 2 (the identification unknowns, §6.5).
enum class NonlinearParameter { c111 = 0, c1111 = 1, e311 = 2, e3111 = 3 };
inline constexpr int kNonlinearParameterCount = 4;

struct HarmonicBalanceOptions {
  // AFT samples per period. The modal force is a polynomial of degree 3 in (q, V_A, V_B), so
  // the projections are exact for N >= 5 (docs/harmonic_balance.md); 16 leaves margin.
  int samples_per_period = 16;
  double phase_deg = 90.0;  // V_B ahead of V_A (DriveInput::phase_deg)
  int max_newton_iterations = 40;
  double tolerance_um = 1e-9;  // Newton step (scaled unknowns, micrometres)
  // The thermal effect's factors (model/machine/effects.h thermal_factors) on the modal stiffness K_i
  // and damping C_i of both modes, as the simulator applies them: 1 = the parameter file's.
  double stiffness_factor = 1.0;
  double damping_factor = 1.0;
};

// q(t) = offset + cos_m cos(wt) + sin_m sin(wt) of one modal coordinate (m).
struct ModeHarmonics {
  double offset_m = 0.0;
  double cos_m = 0.0;
  double sin_m = 0.0;
  [[nodiscard]] double amplitude_m() const;
};

// One periodic solution (one real branch) of one mode.
struct ModeBranch {
  ModeHarmonics harmonics;
  double tip_amplitude_um = 0.0;  // |phi(L)| A (eq. 30): U = A1, W = phiB(L) A2
  bool stable = false;            // slow-flow criterion, docs/harmonic_balance.md
  int newton_iterations = 0;
  // d(tip_amplitude_um)/d(parameter) for c111, c1111, e311, e3111 (SI units of each).
  std::array<double, kNonlinearParameterCount> tip_amplitude_sensitivity_um{};
};

// All branches of one mode at one operating point, sorted by descending amplitude.
struct ModeResponse {
  std::vector<ModeBranch> branches;
};

struct StatorResponse {
  double amplitude_v = 0.0;
  double frequency_hz = 0.0;
  ModeResponse normal;      // L1, tip normal amplitude U
  ModeResponse tangential;  // B2, tip tangential amplitude W
  [[nodiscard]] const ModeResponse& mode(StatorMode m) const { return m == StatorMode::l1 ? normal : tangential; }
};

// Peak of the amplitude-frequency curve of one mode at one voltage (paper Fig. 9).
struct BackbonePoint {
  double amplitude_v = 0.0;
  double normal_peak_hz = 0.0;
  double normal_peak_um = 0.0;
  double tangential_peak_hz = 0.0;
  double tangential_peak_um = 0.0;
};

// Harmonic balance of eqs. (26)-(27) for one parameter set. Cheap to build (no quadrature:
// the modal constants are given); all methods are const and thread-safe.
class FreeStatorHarmonicBalance {
 public:
  FreeStatorHarmonicBalance(const ModalConstants& constants, const StatorParameters& stator,
                            const HarmonicBalanceOptions& options = {});
  explicit FreeStatorHarmonicBalance(const MotorModel& model, const HarmonicBalanceOptions& options = {});

  // Every real branch of both modes (closed-form seeds polished by AFT Newton), deduplicated,
  // each with its stability. `extra_seeds_*` (e.g. the previous point of a continuation) are
  // polished too, so branches the closed form misses are kept when they are tracked.
  [[nodiscard]] StatorResponse solve(double amplitude_v, double frequency_hz) const;
  [[nodiscard]] ModeResponse solve_mode(StatorMode mode, double amplitude_v, double frequency_hz,
                                        std::span<const ModeHarmonics> extra_seeds = {}) const;

  // AFT Newton from one initial guess; false if it does not converge.
  bool polish(StatorMode mode, double amplitude_v, double frequency_hz, const ModeHarmonics& guess,
              ModeBranch& out) const;

  // §6.3 closed form only (no AFT): the real positive roots, descending amplitude.
  [[nodiscard]] std::vector<ModeHarmonics> closed_form_seeds(StatorMode mode, double amplitude_v,
                                                             double frequency_hz) const;

  // Frequency of maximum amplitude of each mode at each voltage (paper Fig. 9), located by a
  // golden-section search on the largest-amplitude branch around the closed-form estimate.
  [[nodiscard]] BackbonePoint backbone(double amplitude_v) const;

  [[nodiscard]] double tip_lever(StatorMode mode) const;  // |phiL(L)| = 1, |phiB(L)|
  [[nodiscard]] const HarmonicBalanceOptions& options() const { return options_; }

 private:
  struct Mode {
    double mass_kg = 0.0;
    double damping_n_s_m = 0.0;
    double tip_lever = 1.0;
    ModeForceCoefficients force;
    // Electrical coefficients (group A, group B) that multiply the non-linear parameters,
    // for the sensitivities (X1..X4 of Appendix A).
    std::array<ElectricalCoefficient, 5> electrical{};
    double cubic_shape = 0.0;      // beta1 or beta2
    double quadratic_shape = 0.0;  // alpha1 or 0
  };
  struct Drive {
    double amplitude_v = 0.0;
    double omega_rad_s = 0.0;
  };

  [[nodiscard]] const Mode& mode_data(StatorMode m) const { return modes_[static_cast<int>(m)]; }
  [[nodiscard]] Drive drive(double amplitude_v, double frequency_hz) const;
  void fill_sensitivities(const Mode& mode, const Drive& d, ModeBranch& branch, const double (&jacobian)[3][3]) const;
  void peak(StatorMode mode, double amplitude_v, double& peak_hz, double& peak_um) const;

  HarmonicBalanceOptions options_;
  double amplitude_per_volt_ = 0.5;
  std::array<Mode, 2> modes_{};
  double cos_phase_ = 0.0;
  double sin_phase_ = 1.0;
  std::vector<double> cos_table_;
  std::vector<double> sin_table_;
};

// Quasi-static sweeps (continuation): every branch at every point, plus the index of the
// branch an experiment sweeping in the given order follows (nearest stable branch to the
// previous followed state; a jump when that branch ends at a fold). -1 if none.
struct SweepPoint {
  StatorResponse response;
  int followed_normal = -1;
  int followed_tangential = -1;
};

[[nodiscard]] std::vector<SweepPoint> sweep_frequency(const FreeStatorHarmonicBalance& hb, double amplitude_v,
                                                      std::span<const double> frequencies_hz);
[[nodiscard]] std::vector<SweepPoint> sweep_voltage(const FreeStatorHarmonicBalance& hb, double frequency_hz,
                                                    std::span<const double> amplitudes_v);

}  // namespace swum
