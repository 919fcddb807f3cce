#include "model/machine/drive.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace swum {
namespace {

TEST(DrivePhasor, RotationTracksSinCosOverManySteps) {
  const double dt = 1e-9 * 260.41666666666669;
  const DriveInput in{400.0, 40123.0, 90.0, 0.0};
  const auto w = make_drive_waveform(in, 0.5, dt);
  double s = 0.0;
  double c = 1.0;
  const int n = 2'000'000;
  for (int k = 0; k < n; ++k) {
    rotate_phasor(w, s, c);
    if ((k & 63) == 63) renormalise_phasor(s, c);
  }
  const double theta = 2 * std::numbers::pi * 40123.0 * n * dt;
  EXPECT_NEAR(s, std::sin(theta), 1e-8);
  EXPECT_NEAR(c, std::cos(theta), 1e-8);
  EXPECT_NEAR(s * s + c * c, 1.0, 1e-14);
}

TEST(DrivePhasor, VoltagesAndPhaseSign) {
  const DriveInput in{400.0, 40000.0, 90.0, 0.0};
  const auto w = make_drive_waveform(in, 0.5, 1e-7);
  const double th = 0.3;
  auto v = drive_voltages(w, std::sin(th), std::cos(th));
  EXPECT_NEAR(v.va_v, 200 * std::sin(th), 1e-12);
  EXPECT_NEAR(v.vb_v, 200 * std::cos(th), 1e-12);  // V_B = V0 cos(wt) at +90 deg
  const auto wr = make_drive_waveform({400.0, 40000.0, -90.0, 0.0}, 0.5, 1e-7);
  v = drive_voltages(wr, std::sin(th), std::cos(th));
  EXPECT_NEAR(v.vb_v, -200 * std::cos(th), 1e-12);
}

}  // namespace
}  // namespace swum
