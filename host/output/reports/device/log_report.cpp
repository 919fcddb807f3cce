#include "output/reports/device/log_report.h"

#include <algorithm>

#include "formats/number_format.h"

namespace swum::host {

std::string log_run_summary(const LogRunCounts& counts, const std::string& device, const std::string& out_path) {
  const double rate = static_cast<double>(counts.samples) / std::max(counts.elapsed_s, 1e-9);
  return std::to_string(counts.samples) + " samples in " + format_number(counts.elapsed_s, "%.2f") + " s from " +
         device + " (" + format_number(rate, "%.1f") + " per s) -> " + out_path + "; " + std::to_string(counts.gaps) +
         " gaps, " + std::to_string(counts.missing) + " samples missing\n";
}

}  // namespace swum::host
