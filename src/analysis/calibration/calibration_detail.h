// Steps shared by the two calibrations (calibration.h on sweeps, calibration_facts.h on
// facts): the free parameters by name, the choice of the free set from the Fisher
// information, and the record of a parameter held at its prior.
#pragma once

#include <Eigen/Dense>

#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/calibration/calibration.h"
#include "analysis/fit/free_parameter.h"

namespace swum {

// What a calibration fits or chooses from, around `prior`: options.free when given, else
// options.candidates, else every applicable candidate, in that order. Throws
// std::invalid_argument for an unknown, repeated or inapplicable name, or an empty pool.
[[nodiscard]] std::vector<FreeParameter> calibration_pool(const CalibrationOptions& options,
                                                          const MotorParameters& prior);

// The free set (calibration.h, step 1): `pool` in its order of preference. j: the Jacobian of
// the residuals at the prior, one row per residual divided by its noise (or tolerance), one
// column per parameter of `pool` in theta units (spreads). Fills `report` (one entry per pool
// parameter) and returns the chosen columns.
[[nodiscard]] std::vector<std::size_t> select_free_set(const Eigen::MatrixXd& j, const std::vector<FreeParameter>& pool,
                                                       const CalibrationOptions& options,
                                                       std::vector<CandidateInformation>& report);

// `start`, then count - 1 seeded random starts uniform within +-1.5 spreads of the origins
// (inside the bounds).
[[nodiscard]] std::vector<std::vector<double>> fit_starts(const std::vector<double>& start,
                                                          const std::vector<FreeParameter>& free, int count,
                                                          std::mt19937_64& rng);

// The parameter that goes back to its prior after a fit (calibration.h, step 3), and why: one
// that ended on a bound first (the data push it past what a motor of this design can be; its
// standard error describes no constrained estimate), else the one whose standard error is the
// most prior spreads above options.max_spread_fraction. No index: every parameter is identified.
struct Undetermined {
  std::optional<std::size_t> index;
  std::string reason;  // ends in "held at its prior"
};
[[nodiscard]] Undetermined least_determined(const std::vector<double>& values,
                                            const std::vector<double>& standard_errors,
                                            const std::vector<FreeParameter>& free, const CalibrationOptions& options);

// True when `value` lies on one of f's bounds (within 1e-6 spread).
[[nodiscard]] bool at_bound(const FreeParameter& f, double value);

// The next round of step 3: `which` (an index is set) leaves the free set and the values to
// start from; returned as not identifiable, held at its prior, with the reason.
[[nodiscard]] CalibratedParameter hold_at_prior(const Undetermined& which, std::vector<FreeParameter>& free,
                                                std::vector<double>& start);

// Relative RMS of the prior's and the fit's residuals on the training and held-out values, and
// the held-out evidence of fit against prior (result.prior_predictions, fitted_predictions).
void score_on_measurements(const MeasurementSet& set, const ResidualModel& model, const std::vector<std::size_t>& train,
                           const std::vector<std::size_t>& test, const CalibrationOptions& options,
                           CalibrationResult& result);

}  // namespace swum
