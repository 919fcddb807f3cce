#include "output/reports/device/control_report.h"

#include <set>

#include "formats/number_format.h"

namespace swum::host {
namespace {

std::string describe_codes(const std::set<int>& codes) {
  std::string text;
  for (const int c : codes) text += (text.empty() ? "" : ",") + std::to_string(c);
  return text.empty() ? "none" : text;
}

}  // namespace

std::string control_run_summary(const SpeedControlResult& result, const SpeedControlSettings& settings, bool lockstep,
                                const std::string& out_path) {
  return std::to_string(result.cycles) + " cycles at " + format_number(settings.target_mm_s, "%.6f") + " mm/s (" +
         (lockstep ? "lockstep" : "wall time") + ", recover " + describe_codes(settings.recoverable_faults) + ") -> " +
         out_path + "; mean |error| over the last half " + format_number(result.mean_abs_error_last_half_mm_s, "%.3f") +
         " mm/s; " + std::to_string(result.faults_seen) + " faults, " + std::to_string(result.retries) + " retries\n";
}

}  // namespace swum::host
