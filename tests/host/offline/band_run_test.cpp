// `swum band`'s part on this machine (host/offline/band_run.h): the grid's checks name the
// option, and the threaded run gives the rows src/'s operating_band gives on one thread.
#include "offline/band_run.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

#include "calibrated_parameters.h"
#include "output/value_lists.h"

namespace swum::host {
namespace {

BandGrid coarse_grid(std::vector<double> voltages, std::vector<double> rises_k = {0.0}) {
  BandGrid grid;
  grid.voltages = std::move(voltages);
  grid.temperature_rises_k = std::move(rises_k);
  grid.frequencies_hz = parse_range_or_value("38750:40500:50", "--frequency-hz");
  grid.margin_hz = 100.0;
  return grid;
}

TEST(OperatingBand, ChecksNameTheOption) {
  auto message = [](const BandGrid& grid) {
    try {
      check_band_grid(grid, 0);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  BandGrid grid = coarse_grid({400.0});
  EXPECT_EQ(message(grid), "no error");
  grid.temperature_rises_k = {400.0};
  EXPECT_EQ(message(grid), "--temperature-rise-k: 400 is outside 0..300 K");
  grid.temperature_rises_k = {0.0};
  grid.margin_hz = -1.0;
  EXPECT_EQ(message(grid), "--margin-hz: must be within 0..10000");
  grid.margin_hz = 100.0;
  try {
    check_band_grid(grid, -1);
    FAIL() << "--jobs -1 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--jobs: must be within 0..1024 (0 = all cores)");
  }

  grid = coarse_grid({400.0}, {0.0, 20.0});
  try {
    check_band_thermal(grid, test::calibrated_parameters(), "li2019.toml");
    FAIL() << "a rise without the thermal effect";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "--temperature-rise-k: 20 K needs the thermal effect, but li2019.toml has [effects.thermal] enabled = "
              "false");
  }
  MotorParameters hot = test::calibrated_parameters();
  hot.effects.thermal.enabled = true;
  EXPECT_NO_THROW(check_band_thermal(grid, hot, "hot.toml"));
  EXPECT_NO_THROW(check_band_thermal(coarse_grid({400.0}), test::calibrated_parameters(), "li2019.toml"));
}

// Nine chains: two tasks of lanes, on the host's pool of two threads.
TEST(BandRun, OnTwoThreadsGivesTheRowsOfOne) {
  const MotorModel model(test::calibrated_parameters());
  BandGrid grid = coarse_grid({200.0, 300.0, 400.0});
  grid.loads_n = {0.0, 1.0, 0.5};
  std::atomic<int> points{0};  // point_done runs on the workers
  const auto two = run_operating_band(model, grid, 2, [&] { ++points; });
  const auto one = operating_band(model, grid, serial_for, 1);
  ASSERT_EQ(two.size(), 9u);
  ASSERT_EQ(one.size(), 9u);
  EXPECT_EQ(points.load(), 9 * 36);  // nine chains of 36 frequencies
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].pick.frequency_hz, two[i].pick.frequency_hz);
    EXPECT_EQ(one[i].pick.peak_frequency_hz, two[i].pick.peak_frequency_hz);
    EXPECT_EQ(one[i].curve.size(), two[i].curve.size());
  }
}

}  // namespace
}  // namespace swum::host
