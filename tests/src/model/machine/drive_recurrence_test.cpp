#include "model/machine/drive_recurrence.h"

#include <gtest/gtest.h>

#include <cmath>

#include "calibrated_parameters.h"
#include "model/motor_model.h"

namespace swum {
namespace {

// The recurrence's cubic coefficients against the voltages at theta_n put into eqs. 14-15 (the
// modal force of both modes at a few coordinates), step after step from one seed.
struct Drive {
  double amplitude_v, frequency_hz, phase_deg, gain_a, gain_b;
};

class DriveRecurrenceAgrees : public ::testing::TestWithParam<Drive> {};

TEST_P(DriveRecurrenceAgrees, WithTheVoltagesStepByStep) {
  const Drive d = GetParam();
  const MotorModel model{test::calibrated_parameters()};
  const MotorCoefficients& k = model.coefficients();
  const PairedForceCoefficients m = make_paired_force_coefficients(k.stator);
  DriveWaveform w = make_drive_waveform({d.amplitude_v, d.frequency_hz, d.phase_deg, 0.0}, k.drive_amplitude_per_volt,
                                        model.time_step_s());
  w.amplitude_a_v *= d.gain_a;
  w.amplitude_b_v *= d.gain_b;
  const double theta0 = 0.7;
  const DoublePair constant{0.25, 0.0};
  DriveRecurrence r;
  r.seed(m, constant, w, std::sin(theta0), std::cos(theta0));
  const double step_rad = w.angular_frequency_rad_s * model.time_step_s();
  // Force scale: the linear spring force at 1 um of the L1 mode.
  const double scale_n = m.k[0] * 1e-6;
  double worst_force = 0.0, worst_phasor = 0.0;
  for (int n = 0; n < 64; ++n) {  // one housekeeping block: the simulator reseeds after it
    const double theta = theta0 + n * step_rad;
    const DriveVoltages u = drive_voltages(w, std::sin(theta), std::cos(theta));
    worst_phasor = std::max(
        {worst_phasor, std::abs(r.sin_theta() - std::sin(theta)), std::abs(r.cos_theta() - std::cos(theta))});
    for (const double q_um : {-2.0, 0.0, 0.5, 3.0}) {
      const DoublePair q{q_um * 1e-6, q_um * 1e-6};
      const DoublePair direct = modal_forces_n(m, q, u.va_v, u.vb_v) + constant;
      const DoublePair stepped = modal_forces_n(r.cubic(), m.k3, q);
      worst_force = std::max({worst_force, std::abs(stepped[0] - direct[0]), std::abs(stepped[1] - direct[1])});
    }
    r.next();
  }
  EXPECT_LT(worst_force, 1e-12 * scale_n);
  EXPECT_LT(worst_phasor, 1e-13);  // ~n eps / sin(w dt): 2e-14 seen
}

INSTANTIATE_TEST_SUITE_P(Drives, DriveRecurrenceAgrees,
                         ::testing::Values(Drive{400.0, 40000.0, 90.0, 1.0, 1.0},   // commensurate: 48 steps
                                           Drive{100.0, 40317.0, 90.0, 1.0, 1.0},   // not
                                           Drive{250.0, 39500.0, -90.0, 1.0, 1.0},  // reverse
                                           Drive{400.0, 40100.0, 60.0, 1.0, 0.0},   // open phase B
                                           Drive{300.0, 41000.0, 90.0, 0.5, 1.0}),  // weak phase A
                         [](const ::testing::TestParamInfo<Drive>& info) {
                           return "case" + std::to_string(info.index);
                         });

// Without a drive the coefficients are the constants, exactly, at every step.
TEST(DriveRecurrence, ZeroDriveIsConstant) {
  const MotorModel model{test::calibrated_parameters()};
  const PairedForceCoefficients m = make_paired_force_coefficients(model.coefficients().stator);
  const DriveWaveform w = make_drive_waveform({0.0, 40000.0, 90.0, 0.0}, 1.0, model.time_step_s());
  DriveRecurrence r;
  r.seed(m, DoublePair{0.0, 0.0}, w, 0.3, std::sqrt(1.0 - 0.09));
  for (int n = 0; n < 1000; ++n) {
    const ModalCubic c = r.cubic();
    ASSERT_EQ(c.c0[0], 0.0);
    ASSERT_EQ(c.c0[1], 0.0);
    ASSERT_EQ(c.c1[0], -m.k[0]);
    ASSERT_EQ(c.c1[1], -m.k[1]);
    ASSERT_EQ(c.c2[0], -m.k2[0]);
    r.next();
  }
}

// Unreseeded, rounding makes the recurrence drift slowly (~n eps / sin(w dt)): still within
// 1e-9 of the force scale after 10^5 steps, so a 64-step reseed leaves nothing to see.
TEST(DriveRecurrence, DriftsSlowlyWithoutReseeding) {
  const MotorModel model{test::calibrated_parameters()};
  const PairedForceCoefficients m = make_paired_force_coefficients(model.coefficients().stator);
  const DriveWaveform w = make_drive_waveform({400.0, 40123.0, 90.0, 0.0},
                                              model.coefficients().drive_amplitude_per_volt, model.time_step_s());
  DriveRecurrence r;
  r.seed(m, DoublePair{0.0, 0.0}, w, 0.0, 1.0);
  constexpr int kSteps = 100000;
  for (int n = 0; n < kSteps; ++n) r.next();
  const double theta = kSteps * w.angular_frequency_rad_s * model.time_step_s();
  const DriveVoltages u = drive_voltages(w, std::sin(theta), std::cos(theta));
  const DoublePair q{1e-6, 1e-6};
  const DoublePair direct = modal_forces_n(m, q, u.va_v, u.vb_v);
  const DoublePair stepped = modal_forces_n(r.cubic(), m.k3, q);
  EXPECT_NEAR(stepped[0], direct[0], 1e-9 * m.k[0] * 1e-6);
  EXPECT_NEAR(stepped[1], direct[1], 1e-9 * m.k[1] * 1e-6);
}

}  // namespace
}  // namespace swum
