#include "output/reports/model/validation_plots.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>

namespace swum::host {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::path(testing::TempDir()) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

XyCurve line(double offset) { return {{0.0, 1.0, 2.0}, {offset, offset + 1.0, offset + 4.0}}; }

// Curves made by hand in the shapes validation_curves returns (no model run).
ValidationCurves curves() {
  ValidationCurves c;
  c.speed_vs_voltage_nonlinear = line(0.0);
  c.speed_vs_voltage_linear = line(1.0);
  for (double paper_v : {100.0, 250.0, 400.0})
    c.speed_vs_frequency.push_back({paper_v, line(paper_v), line(paper_v + 1)});
  c.peak_vs_voltage_nonlinear = {{100.0, 250.0, 400.0}, {40.3, 40.1, 39.7}};
  c.peak_vs_voltage_linear = {{100.0, 250.0, 400.0}, {40.5, 40.5, 40.5}};
  c.speed_vs_load = {{300.0, 40060.0, line(2.0)}, {400.0, 40400.0, line(3.0)}};
  for (double paper_v : {100.0, 400.0})
    c.orbit_vs_voltage.push_back({paper_v, 39500.0, {{-1.0, 0.0, 1.0}, {0.0, 1.0, 0.0}}});
  c.orbit_vs_frequency.push_back({400.0, 39000.0, {{-2.0, 0.0, 2.0}, {0.0, 2.0, 0.0}}});
  return c;
}

bool is_png(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return std::string(magic + 1, 3) == "PNG";
}

TEST(ValidationPlots, WritesTheSixPaperFiguresAsPngFiles) {
  const fs::path dir = fresh_dir("validation_plots");
  write_validation_plots(curves(), dir);
  const std::set<std::string> expected{"fig10_tip_trajectory_vs_voltage.png", "fig11_tip_trajectory_vs_frequency.png",
                                       "fig13_speed_vs_voltage.png",          "fig14_speed_vs_frequency.png",
                                       "fig15_peak_frequency_vs_voltage.png", "fig16_speed_vs_load.png"};
  std::set<std::string> written;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) written.insert(e.path().filename().string());
  EXPECT_EQ(written, expected);
  for (const std::string& name : expected) {
    EXPECT_TRUE(is_png(dir / name)) << name;
    EXPECT_GT(fs::file_size(dir / name), 1000u) << name;
  }
}

// Fig. 15 always has the paper's three points, so it is drawn even when no peak was found.
TEST(ValidationPlots, PeakFigureStandsOnThePapersPointsAlone) {
  const fs::path dir = fresh_dir("validation_plots_no_peaks");
  ValidationCurves c = curves();
  c.peak_vs_voltage_nonlinear = {};
  c.peak_vs_voltage_linear = {};
  write_validation_plots(c, dir);
  EXPECT_TRUE(is_png(dir / "fig15_peak_frequency_vs_voltage.png"));
}

// A figure with no point at all (every run diverged) is an error naming its file; the figures
// before it are written.
TEST(ValidationPlots, AFigureWithNothingToDrawIsAnErrorNamingItsFile) {
  const fs::path dir = fresh_dir("validation_plots_empty");
  ValidationCurves c = curves();
  c.speed_vs_load = {{300.0, 40060.0, {}}};
  try {
    write_validation_plots(c, dir);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("fig16_speed_vs_load.png"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(dir / "fig15_peak_frequency_vs_voltage.png"));
  EXPECT_FALSE(fs::exists(dir / "fig10_tip_trajectory_vs_voltage.png"));
}

}  // namespace
}  // namespace swum::host
