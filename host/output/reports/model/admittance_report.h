// What `swum admittance` prints and writes: the measured Y(f) (CSV), the fitted BVD circuit per
// drive level next to the analytic one (text, JSON), and the plots (|Y| and phase against
// frequency per drive level, the admittance circle B against G).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "analysis/admittance/admittance_measurement.h"
#include "analysis/admittance/circuit_fit.h"
#include "analysis/admittance/equivalent_circuit.h"

namespace swum::host {

// One drive level: its Y(f) and the circuit fitted to it.
struct AdmittanceLevel {
  double amplitude_v = 0.0;
  std::vector<AdmittancePoint> points;
  CircuitFit fit;
};

struct AdmittanceReport {
  std::string source;  // the parameter file
  DrivenPhase phase = DrivenPhase::a;
  Mounting mounting = Mounting::free;
  EquivalentCircuit analytic;  // from the modal constants of the mounted stator
  std::vector<AdmittanceLevel> levels;
};

// Columns amplitude_v,frequency_hz,magnitude_siemens,phase_deg,conductance_siemens,
// susceptance_siemens,current_a,diverged (1: the simulator's runaway guard tripped at that point;
// its numbers are not a measurement).
[[nodiscard]] std::string admittance_csv(const AdmittanceReport& report);
[[nodiscard]] std::string admittance_text(const AdmittanceReport& report);
[[nodiscard]] std::string admittance_json(const AdmittanceReport& report);
// One line naming the first level whose points diverged or whose fit failed; empty when none.
[[nodiscard]] std::string admittance_problem(const AdmittanceReport& report);
// admittance_magnitude.png, admittance_phase.png, admittance_circle.png in `dir`; diverged points
// are left out.
void write_admittance_plots(const AdmittanceReport& report, const std::filesystem::path& dir);

}  // namespace swum::host
