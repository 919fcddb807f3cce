// The CSV layout of `swum log` (docs/host.md): the header and one row per telemetry sample.
// Shared by the command and the tests that read logs back as measurements.
#pragma once

#include <cstdio>
#include <optional>
#include <string>

#include "device/device.h"
#include "formats/number_format.h"

namespace swum::host {

inline constexpr const char* kLogCsvHeader =
    "host_time_s,device_time_s,speed_mm_s,position_mm,tip_normal_um,tip_tangential_um,frequency_hz,amplitude_v,"
    "phase_deg,load_n,state,fault_code,last_reject,lateness_p99_us,lateness_max_us,overruns,current_a_a,current_b_a,"
    "phase_a_deg,phase_b_deg,motional_phase_a_deg,motional_phase_b_deg,power_w,stator_temperature_c\n";

// The electrical columns (the last eight of both the log and a live sweep: docs/host.md), to the
// wire's resolution (0.1 mA, 0.01 deg, 0.01 W, 0.01 degC); empty cells when the device did not
// report them. Starts with the separating comma.
inline std::string format_electrical_cells(const std::optional<protocol::ElectricalValues>& e,
                                           const std::optional<double>& stator_temperature_c) {
  std::string cells;
  if (e) {
    char text[160];
    std::snprintf(text, sizeof text, ",%.4f,%.4f,%.2f,%.2f,%.2f,%.2f,%.2f", e->current_a_a, e->current_b_a,
                  e->phase_a_deg, e->phase_b_deg, e->motional_phase_a_deg, e->motional_phase_b_deg, e->power_w());
    cells = text;
  } else {
    cells = ",,,,,,,";
  }
  return cells + "," + (stator_temperature_c ? format_number(*stator_temperature_c, "%.2f") : std::string());
}

// `host_s`: host clock since the log began; the device clock cell is empty without one.
inline std::string format_log_row(double host_s, const DeviceTelemetry& t) {
  char line[512];
  const std::string device_time = t.device_time_s ? format_number(*t.device_time_s, "%.3f") : std::string();
  std::snprintf(line, sizeof line, "%.6f,%s,%.3f,%.3f,%.3f,%.3f,%.3f,%.1f,%.2f,%.3f,%d,%d,%d,%.0f,%.0f,%u", host_s,
                device_time.c_str(), t.speed_mm_s, t.position_mm, t.tip_normal_um, t.tip_tangential_um, t.frequency_hz,
                t.amplitude_v, t.phase_deg, t.load_n, t.state, t.fault_code, t.last_reject, t.lateness_p99_us,
                t.lateness_max_us, t.overruns);
  return line + format_electrical_cells(t.electrical, t.stator_temperature_c) + "\n";
}

}  // namespace swum::host
