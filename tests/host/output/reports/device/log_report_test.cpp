#include "output/reports/device/log_report.h"

#include <gtest/gtest.h>

namespace swum::host {
namespace {

TEST(LogRunSummary, SamplesRateGapsAndMissing) {
  EXPECT_EQ(log_run_summary({1000, 3, 12, 10.004}, "modbus tcp://127.0.0.1:1502", "log.csv"),
            "1000 samples in 10.00 s from modbus tcp://127.0.0.1:1502 (100.0 per s) -> log.csv; 3 gaps, 12 samples "
            "missing\n");
  // No time measured: the rate stays finite.
  EXPECT_EQ(log_run_summary({0, 0, 0, 0.0}, "can vcan0", "l.csv"),
            "0 samples in 0.00 s from can vcan0 (0.0 per s) -> l.csv; 0 gaps, 0 samples missing\n");
}

}  // namespace
}  // namespace swum::host
