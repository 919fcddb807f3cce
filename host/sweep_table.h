// The sweep table shared by the offline model sweep and (later) the live-device sweep:
// one row per operating point, the CSV layout, and the speed plot.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace swum::host {

struct SweepRow {
  double vpp = 0.0;
  double frequency_hz = 0.0;
  double load_n = 0.0;
  bool ok = false;            // false: the point failed; numbers below are not meaningful
  std::string status = "ok";  // "ok" or a one-word reason (e.g. "diverged")
  double speed_mm_s = 0.0;
  double tip_normal_um = 0.0;
  double tip_tangential_um = 0.0;
};

/// CSV text: header `vpp,frequency_hz,load_n,speed_mm_s,tip_normal_um,tip_tangential_um,status`
/// then one line per row; a failed row has empty numeric cells, never made-up numbers.
std::string format_sweep_csv(const std::vector<SweepRow>& rows);

/// Speed vs frequency, one curve per (voltage, load); or speed vs voltage when the sweep
/// has a single frequency. Failed rows are left out of the curves.
void write_sweep_plot(const std::vector<SweepRow>& rows, const std::filesystem::path& path);

}  // namespace swum::host
