#include "output/reports/device/track_run_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

namespace swum::host {
namespace {

TEST(TrackRunSummary, OneLineWithTheFinalFrequencyPeakAndSetPoint) {
  TrackRunResult r;
  r.cycles = 3000;
  r.final_frequency_hz = 40123.5;
  r.peak_hz = 39950.0;
  r.phase_setpoint_deg = -12.5;
  r.collapses = 1;
  EXPECT_EQ(track_run_summary(r, true, "phase", "run.csv"),
            "3000 cycles (lockstep, method phase) -> run.csv; final 40123.5 Hz; peak 39950 Hz; phase set-point "
            "-12.5 deg; 1 collapses\n");
  TrackRunResult fixed;
  fixed.cycles = 10;
  fixed.final_frequency_hz = 40400.0;
  EXPECT_EQ(track_run_summary(fixed, false, "fixed", "f.csv"),
            "10 cycles (wall time, method fixed) -> f.csv; final 40400 Hz; peak none; phase set-point none; 0 "
            "collapses\n");
}

TEST(TrackPlotSeries, KeepsKilohertzAndNaNWhereARowCarriesNothing) {
  TrackPlotSeries s;
  TrackRow row;
  row.time_s = 0.5;
  row.frequency_hz = 40100.0;
  row.speed_mm_s = 80.0;
  s.add(row);
  row.time_s = 1.0;
  row.stator_temperature_c = 31.5;
  s.add(row);
  EXPECT_EQ(s.time_s, (std::vector<double>{0.5, 1.0}));
  EXPECT_DOUBLE_EQ(s.frequency_khz[0], 40.1);
  EXPECT_TRUE(std::isnan(s.temperature_c[0]));
  EXPECT_DOUBLE_EQ(s.temperature_c[1], 31.5);
  EXPECT_TRUE(std::isnan(s.phase_deg[1]));  // no electrical reading
}

TEST(WriteTrackPlots, TemperatureAndPhaseOnlyWhenMeasured) {
  TrackPlotSeries s;
  TrackRow row;
  for (int i = 0; i < 3; ++i) {
    row.time_s = 0.1 * i;
    row.frequency_hz = 40000.0 + i;
    row.speed_mm_s = 50.0 + i;
    row.stator_temperature_c = 25.0 + i;
    s.add(row);
  }
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "track_run_report_plots";
  std::filesystem::remove_all(dir);
  write_track_plots(s, dir.string(), "speed");
  EXPECT_TRUE(std::filesystem::exists(dir / "track_frequency.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "track_speed.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "track_temperature.png"));
  EXPECT_FALSE(std::filesystem::exists(dir / "track_phase.png"));
}

}  // namespace
}  // namespace swum::host
