// Identification of the four non-linear electroelastic constants c111, c1111, e311, e3111 from
// free-stator tip amplitudes (paper Sec. 4, model_spec §6.5): bounded non-linear least squares
// (Ceres, Levenberg-Marquardt) on the harmonic balance of harmonic_balance.h, several starts,
// standard errors from the Jacobian, and an identifiability test that keeps parameters the
// data cannot determine at their prior values. docs/identification.md.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/free_stator/amplitude_measurement.h"
#include "analysis/free_stator/harmonic_balance.h"
#include "model/parameters.h"

namespace swum {

struct IdentificationOptions {
  int starts = 6;  // prior, zero (linear model), then seeded random starts
  std::uint64_t seed = 20190475;
  double start_spread = 3.0;   // random starts uniform in +-spread * scale
  double bound_factor = 10.0;  // bounds |p| <= bound_factor * scale (scale: see below)
  // A direction of J^T J (parameters in units of their scale) whose eigenvalue is below this
  // fraction of the largest is flat: the parameters along it are not identifiable.
  double flat_eigenvalue_ratio = 1e-8;
  // Identifiable only if standard error < this * max(|fitted value|, scale). 1 would be the
  // bare "standard error larger than the value" rule; 0.25 also rejects estimates whose 2-sigma
  // interval spans more than half their size (docs/identification.md).
  double max_relative_standard_error = 0.25;
  double significance_sigmas = 2.0;  // "significantly different from zero": |p| > this * se
  // Residual r = (predicted - measured) / max(measured, floor); floor = this * axis maximum.
  double amplitude_floor_fraction = 0.01;
  int max_iterations = 200;
  HarmonicBalanceOptions harmonic_balance;
};

struct ParameterEstimate {
  NonlinearParameter parameter = NonlinearParameter::c1111;
  std::string_view key;  // TOML key in [stator], e.g. "c1111_pa"
  double prior = 0.0;    // value of the input parameter set
  double scale = 0.0;    // max(|prior|, Table-2 magnitude): the size the data must resolve
  double value = 0.0;    // fitted when identifiable, else the prior
  double standard_error = std::numeric_limits<double>::infinity();  // +inf: not identified
  bool identifiable = false;
  bool significant = false;  // identifiable and |value| > significance_sigmas * standard_error
  std::string reason;        // why it is not identifiable (empty otherwise)
};

struct PointPrediction {
  AmplitudeMeasurement measurement;
  std::optional<double> predicted_normal_um;      // on the stable branch nearest the data
  std::optional<double> predicted_tangential_um;  // (empty when the axis was not measured)
};

struct IdentificationResult {
  bool ok = false;
  std::string failure;  // why not ok
  std::array<ParameterEstimate, kNonlinearParameterCount> parameters{};
  StatorParameters fitted_stator;  // prior with the identified parameters replaced
  std::vector<PointPrediction> predictions;
  int residual_count = 0;
  double rms_relative_residual = 0.0;  // sqrt(mean r^2)
  double rms_normal_um = std::numeric_limits<double>::quiet_NaN();
  double rms_tangential_um = std::numeric_limits<double>::quiet_NaN();
  // Eigenvalues of J^T J for all four parameters in units of their scale at the final
  // parameters, ascending, and the matching eigenvectors (columns): the flat directions.
  std::array<double, kNonlinearParameterCount> information_eigenvalues{};
  std::array<std::array<double, kNonlinearParameterCount>, kNonlinearParameterCount> information_eigenvectors{};
  int starts_run = 0;  // least-squares solves in total (all rounds)
  int rounds = 0;      // fits (one more after each parameter fixed at its prior)
};

[[nodiscard]] std::string_view nonlinear_parameter_key(NonlinearParameter p);
[[nodiscard]] double nonlinear_parameter_value(const StatorParameters& s, NonlinearParameter p);
void set_nonlinear_parameter(StatorParameters& s, NonlinearParameter p, double value);

// Tip amplitude of `mode` on the stable branch nearest to `measured_um` (the largest stable
// branch without a measurement); nullopt if the harmonic balance finds no branch.
[[nodiscard]] std::optional<ModeBranch> predicted_branch(const FreeStatorHarmonicBalance& hb, StatorMode mode,
                                                         double amplitude_v, double frequency_hz,
                                                         std::optional<double> measured_um);

// Needs at least kNonlinearParameterCount amplitude values (ok = false otherwise).
[[nodiscard]] IdentificationResult identify_nonlinear_parameters(const MotorParameters& prior,
                                                                 std::span<const AmplitudeMeasurement> data,
                                                                 const IdentificationOptions& options = {});

}  // namespace swum
