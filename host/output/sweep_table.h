// The sweep table shared by the offline model sweep and the live-device sweep:
// one row per operating point, the CSV layout, and the speed plot.
// (The live sweep adds a per-point spread column and records when and in which continuous
// sweep each point was taken.)
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace swum::host {

// Live sweeps: the electrical port (docs/protocols.md "Electrical port"), means over the dwell.
struct SweepElectrical {
  double current_a_a = 0.0, current_b_a = 0.0;  // peak of the drive-frequency component
  double phase_a_deg = 0.0, phase_b_deg = 0.0;  // current vs voltage, + = current leads
  double motional_phase_a_deg = 0.0, motional_phase_b_deg = 0.0;
  double power_w = 0.0;  // real power, both phases
  bool operator==(const SweepElectrical&) const = default;
};

// Model sweeps: the figures a board is sized with (electrical.h ElectricalReadings, over the
// point's last steady-state window), per phase.
struct SweepSizing {
  double current_rms_a_a = 0.0, current_rms_b_a = 0.0;          // true RMS of the terminal current
  double current_peak_a_a = 0.0, current_peak_b_a = 0.0;        // largest |I| sampled
  double voltage_a_v = 0.0, voltage_b_v = 0.0;                  // amplitude of the voltage applied
  double power_a_w = 0.0, power_b_w = 0.0;                      // real power
  double apparent_power_a_va = 0.0, apparent_power_b_va = 0.0;  // V_rms I_rms
  double power_factor_a = 0.0, power_factor_b = 0.0;            // P / S
  bool operator==(const SweepSizing&) const = default;
};

struct SweepRow {
  double amplitude_v = 0.0;
  double frequency_hz = 0.0;
  double load_n = 0.0;
  bool ok = false;            // false: the point failed; numbers below are not meaningful
  std::string status = "ok";  // "ok" or a one-word reason (e.g. "diverged")
  double speed_mm_s = 0.0;
  double tip_normal_um = 0.0;
  double tip_tangential_um = 0.0;
  // Live sweeps: standard deviation of the speed samples over the dwell (< 0: not measured).
  double speed_spread_mm_s = -1.0;
  // Live sweeps: device clock at the start of the point's dwell window (for a point that
  // failed, when it was given up), counted from the start of the sweep session ...
  std::optional<double> time_s = std::nullopt;
  // ... and the continuous curve it belongs to: one per (load, voltage) pass from the top
  // frequency down, a new one whenever the drive had to be started again after a fault.
  std::optional<int> sweep = std::nullopt;
  // Live sweeps, when the device reports them (empty cells otherwise): the electrical port and
  // the stator temperature, means over the dwell window.
  std::optional<SweepElectrical> electrical = std::nullopt;
  std::optional<double> stator_temperature_c = std::nullopt;
  // Model sweeps: the sizing figures (empty cells for a failed point or one at 0 V).
  std::optional<SweepSizing> sizing = std::nullopt;
};

/// Statuses (the one-word `status` column): `ok`; from the model `unsettled` (values are its
/// best estimate) and `diverged`; from a device `fault_numerical`, `fault_command_timeout`,
/// `fault_<code>`, `timeout`, `no_drive`. True when the motor (or model) itself failed at the
/// point — for the picking rule a collapse — false when the point was simply not measured.
bool is_physical_failure(const SweepRow& row);

/// The optional columns of a sweep file. A device sweep always has all four (kDeviceSweep),
/// a model sweep none (kModelSweep): their files are written row by row, so the header cannot
/// wait for the rows.
struct SweepLayout {
  bool time = false;        // time_s and ...
  bool sweep = false;       // ... sweep, after load_n
  bool spread = false;      // speed_spread_mm_s, after tip_tangential_um
  bool electrical = false;  // kElectricalColumns, after status
  bool sizing = false;      // kSizingColumns, after those
  bool operator==(const SweepLayout&) const = default;
};
inline constexpr SweepLayout kModelSweep{false, false, false, true, true};
inline constexpr SweepLayout kDeviceSweep{true, true, true, true, false};
/// The electrical columns of a live sweep, in order (the same names as `swum log`'s).
inline constexpr const char* kElectricalColumns[] = {"current_a_a", "current_b_a",          "phase_a_deg",
                                                     "phase_b_deg", "motional_phase_a_deg", "motional_phase_b_deg",
                                                     "power_w",     "stator_temperature_c"};

/// The sizing columns of a model sweep, in SweepSizing's order.
inline constexpr const char* kSizingColumns[] = {"current_rms_a_a",     "current_rms_b_a", "current_peak_a_a",
                                                 "current_peak_b_a",    "voltage_a_v",     "voltage_b_v",
                                                 "power_a_w",           "power_b_w",       "apparent_power_a_va",
                                                 "apparent_power_b_va", "power_factor_a",  "power_factor_b"};

/// The columns the rows use: time/sweep when any row has one, spread when any row has one.
SweepLayout sweep_layout_of(const std::vector<SweepRow>& rows);
/// The header line and one row line (with their '\n') of format_sweep_csv.
std::string format_sweep_header(const SweepLayout& layout);
std::string format_sweep_row(const SweepLayout& layout, const SweepRow& row);

/// CSV text (the columns of sweep_layout_of(rows)): header
/// `amplitude_v,frequency_hz,load_n,speed_mm_s,tip_normal_um,tip_tangential_um,status` then one line per row; a failed
/// row has empty measured cells, never made-up numbers. When any row has a time or a sweep id (live sweeps), `time_s`
/// and `sweep` follow `load_n`; when any row has a measured spread, a `speed_spread_mm_s` column follows
/// `tip_tangential_um`; when any row has electrical values or a stator temperature, the eight
/// kElectricalColumns follow `status` (empty cells where a row has none); when any row has sizing
/// figures (model sweeps), the twelve kSizingColumns follow those.
std::string format_sweep_csv(const std::vector<SweepRow>& rows);

/// Reads a sweep CSV (the layouts above; columns found by name, `time_s`, `sweep`,
/// `speed_spread_mm_s`, `status` and the electrical columns optional; a row's electrical values
/// are read when all seven of their cells are filled, the sizing figures when all twelve are). A row is ok when status
/// is "ok", "unsettled" (or absent) and the speed is present. Throws std::runtime_error naming `source` and the line of
/// a bad row, std::invalid_argument naming them and the column of a cell that is not a finite number.
std::vector<SweepRow> parse_sweep_csv(const std::string& text, const std::string& source);
/// Speed vs frequency, one curve per (voltage, load); or speed vs voltage when the sweep
/// has a single frequency. Failed rows are left out of the curves.
void write_sweep_plot(const std::vector<SweepRow>& rows, const std::filesystem::path& path);

}  // namespace swum::host
