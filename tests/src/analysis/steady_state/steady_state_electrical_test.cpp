// The electrical port in the steady states (SteadyStateResult::electrical) on the calibrated
// motor (config/li2019.toml): the scalar path, the SIMD lanes and the emulator's port
// (MotorSimulator::advance(steps, ElectricalSums&)) report the same currents and phases; the
// electrical real power balances the modal damping, the contact slip and what the mover takes
// over the validation grid; far from resonance the current is the clamped capacitance's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "analysis/steady_state/steady_state.h"
#include "analysis/steady_state/steady_state_batch.h"
#include "calibrated_parameters.h"
#include "model/motor_model.h"
#include "model/simulation/simulator.h"

namespace swum {
namespace {

// Amplitude, frequency and load in OperatingPoint's order; 90 deg, cold, from rest.
OperatingPoint at(double amplitude_v, double frequency_hz, double load_n = 0.0) {
  return {amplitude_v, frequency_hz, load_n};
}

std::string name(const OperatingPoint& p) {
  char text[80];
  std::snprintf(text, sizeof text, "%g V, %g Hz, %g N", p.amplitude_v, p.frequency_hz, p.load_n);
  return text;
}

// The emulator's measurement at the point: a fresh MotorSimulator, the steady state's settle and
// as many windows as the steady state ran, the last window's sums read as swum-emu reads them.
ElectricalReadings emulator_port(const MotorModel& model, const OperatingPoint& p, int windows) {
  const SteadyStateOptions options;
  MotorSimulator sim(model);
  sim.set_drive({p.amplitude_v, p.frequency_hz, p.phase_deg, p.load_n});
  const double dt = sim.time_step_s();
  sim.advance(static_cast<std::uint64_t>(std::llround(options.settle_s / dt)));
  ElectricalSums sums;
  for (int k = 0; k < windows; ++k) {
    sums = ElectricalSums{};
    sim.advance(static_cast<std::uint64_t>(std::llround(options.window_s / dt)), sums);
  }
  return electrical_readings(sums, p.phase_deg);
}

void expect_same_port(const ElectricalReadings& a, const ElectricalReadings& b, double relative, double phase_deg) {
  ASSERT_TRUE(a.valid);
  ASSERT_TRUE(b.valid);
  auto close = [relative](double x, double y) { EXPECT_NEAR(x, y, relative * std::max(std::abs(y), 1e-3)); };
  close(a.current_a_a, b.current_a_a);
  close(a.current_b_a, b.current_b_a);
  close(a.rms_current_a_a, b.rms_current_a_a);
  close(a.rms_current_b_a, b.rms_current_b_a);
  close(a.peak_current_a_a, b.peak_current_a_a);
  close(a.peak_current_b_a, b.peak_current_b_a);
  close(a.motional_current_a_a, b.motional_current_a_a);
  close(a.power_a_w, b.power_a_w);
  close(a.power_b_w, b.power_b_w);
  close(a.voltage_a_v, b.voltage_a_v);
  close(a.apparent_power_b_va, b.apparent_power_b_va);
  EXPECT_NEAR(a.power_factor_a, b.power_factor_a, relative);
  EXPECT_NEAR(a.phase_a_deg, b.phase_a_deg, phase_deg);
  EXPECT_NEAR(a.phase_b_deg, b.phase_b_deg, phase_deg);
  EXPECT_NEAR(a.motional_phase_a_deg, b.motional_phase_a_deg, phase_deg);
  EXPECT_NEAR(a.motional_phase_b_deg, b.motional_phase_b_deg, phase_deg);
}

// Near the 400 V speed peak (39600 Hz), on the flank with a 1 N load, and at 100 V. The scalar
// path and the emulator's port run the same MotorSimulator steps (the window statistics only
// observe): the same readings to the last bits (1e-12). The lanes agree with the scalar step to
// rounding (they contract multiply-adds differently; their speeds agree to 1e-6 relative,
// steady_state_batch_test.cpp): the currents to 1e-6 relative and the phases to 1e-4 deg.
TEST(SteadyStateElectrical, ScalarBatchAndEmulatorPortAgree) {
  const MotorModel model(test::calibrated_parameters());
  const std::vector<OperatingPoint> points{at(400.0, 39600.0), at(300.0, 40060.0, 1.0), at(100.0, 40300.0)};
  const std::vector<SteadyStateResult> batch = run_points_to_steady_state(model, points);
  for (std::size_t k = 0; k < points.size(); ++k) {
    SCOPED_TRACE(name(points[k]));
    const SteadyStateResult scalar = run_to_steady_state(model, points[k]);
    ASSERT_TRUE(scalar.ok) << scalar.failure;
    const ElectricalReadings emulator = emulator_port(model, points[k], scalar.windows);
    const ElectricalReadings& s = scalar.electrical;
    std::printf("%s: I %.5f A rms (peak %.5f, fundamental %.5f) at %.3f deg, motional %.5f A at %.3f deg, "
                "P %.5f + %.5f W, S %.4f VA, PF %.4f, V %.3f V\n",
                name(points[k]).c_str(), s.rms_current_a_a, s.peak_current_a_a, s.current_a_a, s.phase_a_deg,
                s.motional_current_a_a, s.motional_phase_a_deg, s.power_a_w, s.power_b_w, s.apparent_power_a_va,
                s.power_factor_a, s.voltage_a_v);
    expect_same_port(s, emulator, 1e-12, 1e-9);
    expect_same_port(batch[k].electrical, s, 1e-6, 1e-4);
    // What a board sees: the terminal voltage is the command (no droop on this motor), the
    // current leads it (C0 dominates) and real power flows in.
    EXPECT_NEAR(s.voltage_a_v, points[k].amplitude_v, 1e-6 * points[k].amplitude_v);
    EXPECT_NEAR(s.voltage_b_v, points[k].amplitude_v, 1e-6 * points[k].amplitude_v);
    EXPECT_GT(s.phase_a_deg, 0.0);
    EXPECT_GT(s.power_a_w + s.power_b_w, 0.0);
    EXPECT_GE(s.peak_current_a_a, std::sqrt(2.0) * s.rms_current_a_a * 0.95);  // a sine's crest factor
  }
}

// Power balance over a coarse subset of the validation grid (docs/validation.md: speed against
// frequency at 100, 250, 400 V over 39-41 kHz; against voltage at 40 kHz; against load at
// (300 V, 40060 Hz) and (400 V, 39600 Hz)): the electrical real power of both phases equals the
// modal damping power, the slip power at the interface and what the mover receives (load x
// speed, mover damping, guide friction) within 2 %. The gap is the step's error (first order in
// dt for the contact; Electrical.PowerBalanceInSteadyState: 1-1.5 % at the product step). Both
// paths, since the lanes sum the same terms.
TEST(SteadyStateElectrical, PowerBalanceOverTheValidationGrid) {
  const MotorModel model(test::calibrated_parameters());
  std::vector<OperatingPoint> points;
  for (double v : {100.0, 250.0, 400.0}) {
    for (double f : {39200.0, 39600.0, 40000.0, 40400.0, 41000.0}) points.push_back(at(v, f));
  }
  points.push_back(at(50.0, 40000.0));
  for (double load : {1.0, 3.0}) points.push_back(at(300.0, 40060.0, load));
  points.push_back(at(400.0, 39600.0, 2.0));
  points.push_back(at(400.0, 40400.0, 1.0));
  const std::vector<SteadyStateResult> batch = run_points_to_steady_state(model, points);
  double worst = 0.0;
  int loaded_moving = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    SCOPED_TRACE(name(points[k]));
    const SteadyStateResult& r = batch[k];
    ASSERT_FALSE(r.diverged);
    ASSERT_TRUE(r.electrical.valid);
    const double electrical = r.electrical.power_a_w + r.electrical.power_b_w;
    const double sinks = r.damping_power_w + r.slip_power_w + r.mover_power_w;
    const double output = points[k].load_n * 1e-3 * r.speed_mm_s;
    std::printf("%s: electrical %.5f W; damping %.5f, slip %.5f, mover %.5f (load x speed %.5f) W; gap %.3f %%\n",
                name(points[k]).c_str(), electrical, r.damping_power_w, r.slip_power_w, r.mover_power_w, output,
                100.0 * (sinks / electrical - 1.0));
    ASSERT_GT(electrical, 0.0);
    EXPECT_NEAR(sinks, electrical, 0.02 * electrical);
    worst = std::max(worst, std::abs(sinks / electrical - 1.0));
    // The mover's share holds the mechanical output (the rest is mover damping and guide friction).
    EXPECT_GE(r.mover_power_w, output - 0.02 * electrical);
    if (points[k].load_n > 0.0 && r.speed_mm_s > 10.0) ++loaded_moving;
    // The scalar path sums the same powers.
    if (k % 6 == 0) {
      const SteadyStateResult s = run_to_steady_state(model, points[k]);
      EXPECT_NEAR(s.slip_power_w, r.slip_power_w, 1e-5 * electrical);
      EXPECT_NEAR(s.mover_power_w, r.mover_power_w, 1e-5 * electrical);
    }
  }
  EXPECT_GE(loaded_moving, 2) << "the loaded points must move for the output to count";
  std::printf("worst gap %.3f %%\n", 100.0 * worst);
}

// Far below resonance (45 kHz is 5 kHz above both modes; the live board test's band) the
// motional current is small and the phase current is C0's: I_rms = w C0 V / sqrt 2 within 3 %
// (the same definition host.live.board_current_modbus checks on the fundamental), leading the
// voltage by nearly 90 deg, with a power factor near 0.
TEST(SteadyStateElectrical, FarFromResonanceTheCurrentIsTheClampedCapacitance) {
  const MotorModel model(test::calibrated_parameters());
  const double c0_f = model.coefficients().clamped_capacitance_f;
  for (double v : {100.0, 300.0}) {
    const OperatingPoint p = at(v, 45000.0);
    SCOPED_TRACE(name(p));
    SteadyStateOptions options;
    options.max_s = 0.06;
    const SteadyStateResult r = run_to_steady_state(model, p, options);
    ASSERT_TRUE(r.electrical.valid);
    const double expected_rms_a = 2.0 * std::numbers::pi * p.frequency_hz * c0_f * v / std::sqrt(2.0);
    std::printf("%g V, 45 kHz: I_rms %.5f A (w C0 V / sqrt 2 = %.5f A), phase %.2f deg, PF %.4f\n", v,
                r.electrical.rms_current_a_a, expected_rms_a, r.electrical.phase_a_deg, r.electrical.power_factor_a);
    EXPECT_NEAR(r.electrical.rms_current_a_a, expected_rms_a, 0.03 * expected_rms_a);
    EXPECT_NEAR(r.electrical.rms_current_b_a, expected_rms_a, 0.03 * expected_rms_a);
    EXPECT_NEAR(std::abs(r.electrical.phase_a_deg), 90.0, 5.0);
    EXPECT_LT(std::abs(r.electrical.power_factor_a), 0.1);
  }
}

}  // namespace
}  // namespace swum
