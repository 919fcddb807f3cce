#include "output/plot.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>

namespace swum::host {
namespace {

std::filesystem::path scratch_dir() {
  auto dir = std::filesystem::temp_directory_path() /
             ("swum_plot_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(WritePngPlot, WritesAPngFile) {
  const auto path = scratch_dir() / "speed.png";
  PlotSpec spec{"speed", "frequency (kHz)", "speed (mm/s)", {{"100 V", {39.0, 40.0, 41.0}, {1.0, 5.0, 2.0}}}};
  write_png_plot(spec, path);
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  EXPECT_GT(std::filesystem::file_size(path), 1000u);
}

TEST(WritePngPlot, SkipsNonFinitePointsButRefusesAnAllNanPlot) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto dir = scratch_dir();
  PlotSpec partly{"t", "x", "y", {{"s", {1.0, 2.0, 3.0}, {1.0, nan, 3.0}}}};
  EXPECT_NO_THROW(write_png_plot(partly, dir / "partly.png"));
  PlotSpec empty{"t", "x", "y", {{"s", {1.0}, {nan}}}};
  EXPECT_THROW(write_png_plot(empty, dir / "empty.png"), std::runtime_error);
}

TEST(WritePngPlot, UnwritablePathIsAnErrorNotACrash) {
  PlotSpec spec{"t", "x", "y", {{"s", {1.0, 2.0}, {1.0, 2.0}}}};
  try {
    write_png_plot(spec, "/nonexistent-dir/x.png");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.png"), std::string::npos);
  }
}

}  // namespace
}  // namespace swum::host
