// What `swum log` prints besides its CSV rows (output/log_table.h): the run's one-line summary.
#pragma once

#include <cstddef>
#include <string>

namespace swum::host {

/// What a `swum log` run received: samples, the gaps among them and the samples those lost.
struct LogRunCounts {
  std::size_t samples = 0;
  std::size_t gaps = 0;
  std::size_t missing = 0;
  double elapsed_s = 0.0;
};

/// "N samples in S s from DEVICE (R per s) -> OUT; G gaps, M samples missing\n".
std::string log_run_summary(const LogRunCounts& counts, const std::string& device, const std::string& out_path);

}  // namespace swum::host
