// What `swum stator` prints and writes (paper Sec. 4, model_spec §6.2-6.3): every branch of
// the free stator's harmonic balance per operating point as CSV or JSON (with the backbone),
// the backbone as CSV, and the amplitude plots.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "analysis/free_stator/harmonic_balance.h"

namespace swum::host {

// One state of the free stator: one branch of each (independent) mode.
struct StatorRow {
  double amplitude_v = 0.0;
  double frequency_hz = 0.0;
  int branch = 0;  // index over the product of the two modes' branches (descending amplitude)
  int normal_branch = 0;
  int tangential_branch = 0;
  bool normal_stable = false;
  bool tangential_stable = false;
  bool followed = false;  // the state an up-sweep in frequency follows
  double tip_normal_um = 0.0;
  double tip_tangential_um = 0.0;
  bool stable() const { return normal_stable && tangential_stable; }
};

/// One row per combination of a normal and a tangential branch at each swept point.
std::vector<StatorRow> stator_rows(const std::vector<SweepPoint>& sweep);

/// amplitude_v,frequency_hz,branch,stable,tip_normal_um,tip_tangential_um and one line per row.
std::string stator_csv(const std::vector<StatorRow>& rows);

/// amplitude_v and each mode's peak frequency and amplitude, one line per voltage.
std::string stator_backbone_csv(const std::vector<BackbonePoint>& backbone);

/// {"rows": [...], "backbone": [...]} (pretty, ordered keys, '\n' at the end).
std::string stator_json(const std::vector<StatorRow>& rows, const std::vector<BackbonePoint>& backbone);

/// Amplitude of `mode` vs frequency (several frequencies) or vs voltage (one frequency):
/// stable and unstable branches as separate series; the backbone (peak frequency) as a line.
void write_stator_plot(const std::vector<SweepPoint>& sweep, const std::vector<double>& voltages,
                       const std::vector<double>& frequencies, const std::vector<BackbonePoint>& backbone,
                       StatorMode mode, const std::filesystem::path& path);

}  // namespace swum::host
