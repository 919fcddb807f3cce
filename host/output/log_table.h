// The CSV layout of `swum log` (docs/host.md): the header and one row per telemetry sample.
// Shared by the command and the tests that read logs back as measurements.
#pragma once

#include <cstdio>
#include <string>

#include "config/number_format.h"
#include "device/device.h"

namespace swum::host {

inline constexpr const char* kLogCsvHeader =
    "host_time_s,device_time_s,speed_mm_s,position_mm,tip_normal_um,tip_tangential_um,frequency_hz,vpp,"
    "phase_deg,load_n,state,fault_code,last_reject,lateness_p99_us,lateness_max_us,overruns\n";

// `host_s`: host clock since the log began; the device clock cell is empty without one.
inline std::string format_log_row(double host_s, const DeviceTelemetry& t) {
  char line[512];
  const std::string device_time = t.device_time_s ? format_number(*t.device_time_s, "%.3f") : std::string();
  std::snprintf(line, sizeof line, "%.6f,%s,%.3f,%.3f,%.3f,%.3f,%.3f,%.1f,%.2f,%.3f,%d,%d,%d,%.0f,%.0f,%u\n", host_s,
                device_time.c_str(), t.speed_mm_s, t.position_mm, t.tip_normal_um, t.tip_tangential_um, t.frequency_hz,
                t.vpp, t.phase_deg, t.load_n, t.state, t.fault_code, t.last_reject, t.lateness_p99_us,
                t.lateness_max_us, t.overruns);
  return line;
}

}  // namespace swum::host
