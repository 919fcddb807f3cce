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

// Columns amplitude_v,frequency_hz,magnitude_s,phase_deg,conductance_s,susceptance_s,current_a.
[[nodiscard]] std::string admittance_csv(const AdmittanceReport& report);
[[nodiscard]] std::string admittance_text(const AdmittanceReport& report);
[[nodiscard]] std::string admittance_json(const AdmittanceReport& report);
// admittance_magnitude.png, admittance_phase.png, admittance_circle.png in `dir`.
void write_admittance_plots(const AdmittanceReport& report, const std::filesystem::path& dir);

}  // namespace swum::host
