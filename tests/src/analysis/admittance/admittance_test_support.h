// An admittance sweep of a motor and the fit named as the CLI names it, for the admittance tests
// (the calibrated motor is tests/support/calibrated_parameters.h's).
#pragma once

#include <vector>

#include "analysis/admittance/admittance_measurement.h"
#include "analysis/admittance/circuit_fit.h"
#include "analysis/admittance/equivalent_circuit.h"
#include "calibrated_parameters.h"
#include "model/motor_model.h"

namespace swum::test {

inline std::vector<double> frequency_grid(double start_hz, double stop_hz, double step_hz) {
  std::vector<double> f;
  for (double x = start_hz; x <= stop_hz + 1e-6; x += step_hz) f.push_back(x);
  return f;
}

inline std::vector<AdmittancePoint> sweep(const MotorParameters& p, DrivenPhase phase, Mounting mounting,
                                          double amplitude_v, const std::vector<double>& frequencies_hz) {
  AdmittanceSweepOptions o;
  o.phase = phase;
  o.mounting = mounting;
  o.amplitude_v = amplitude_v;
  o.frequencies_hz = frequencies_hz;
  return measure_admittance(p, o);
}

// The fit with its branches named by the analytic circuit's inductances, as swum admittance does.
inline CircuitFit fit_as_the_cli(const MotorParameters& p, DrivenPhase phase, Mounting mounting,
                                 const std::vector<AdmittancePoint>& points) {
  const MotorModel model(mounted_parameters(p, mounting));
  const EquivalentCircuit analytic = analytic_equivalent_circuit(model, phase, mounting);
  CircuitFitOptions options;
  for (std::size_t i = 0; i < kCircuitModes; ++i) options.reference_inductance_h[i] = analytic.branches[i].inductance_h;
  return fit_equivalent_circuit(points, options);
}

}  // namespace swum::test
