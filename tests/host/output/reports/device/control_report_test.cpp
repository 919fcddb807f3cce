#include "output/reports/device/control_report.h"

#include <gtest/gtest.h>

#include "formats/number_format.h"

namespace swum::host {
namespace {

TEST(ControlRunSummary, CyclesTargetModeRecoverableFaultsAndError) {
  SpeedControlResult r;
  r.cycles = 2000;
  r.mean_abs_error_last_half_mm_s = 0.12345;
  r.faults_seen = 2;
  r.retries = 1;
  SpeedControlSettings s;
  s.target_mm_s = -50.0;
  s.recoverable_faults = {7, 1};
  EXPECT_EQ(control_run_summary(r, s, true, "control.csv"),
            "2000 cycles at -50.000000 mm/s (lockstep, recover 1,7) -> control.csv; mean |error| over the last half "
            "0.123 mm/s; 2 faults, 1 retries\n");
  s.recoverable_faults.clear();
  EXPECT_EQ(control_run_summary(r, s, false, "c.csv"),
            "2000 cycles at -50.000000 mm/s (wall time, recover none) -> c.csv; mean |error| over the last half "
            "0.123 mm/s; 2 faults, 1 retries\n");
}

// `--speed-mm-s 1e60` is accepted; its %.6f text (67 characters) was cut at 63, taking the
// fraction and everything after it.
TEST(ControlRunSummary, AHugeTargetIsPrintedWhole) {
  SpeedControlResult r;
  r.cycles = 3;
  SpeedControlSettings s;
  s.target_mm_s = 1e60;
  s.recoverable_faults.clear();
  const std::string text = control_run_summary(r, s, true, "c.csv");
  const std::string digits = format_number(1e60, "%.0f");
  ASSERT_EQ(digits.size(), 60u);
  EXPECT_EQ(text, "3 cycles at " + digits +
                      ".000000 mm/s (lockstep, recover none) -> c.csv; mean |error| over the last half 0.000 mm/s; 0 "
                      "faults, 0 retries\n");
}

}  // namespace
}  // namespace swum::host
