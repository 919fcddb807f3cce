// The amplifier's output network (model/machine/output_network.h, MotorSimulator): an ideal source
// changes nothing, bit for bit; the droop effect's magnitude is the one it always had; the network's
// envelope settles on the steady state of the circuit; a network that makes the terminal voltage
// diverge is refused at load with one line and counted at run time.
#include "model/machine/output_network.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "../simulation/same_state.h"
#include "calibrated_parameters.h"
#include "formats/parameter_file.h"
#include "model/machine/effects.h"
#include "model/simulation/batch_simulator.h"
#include "model/simulation/simulator.h"

namespace swum {
namespace {

constexpr double kPi = std::numbers::pi;

std::string calibrated_text() {
  std::ifstream in(test::source_path("config/li2019.toml"));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// (a) An explicit all-zero [amplifier] section is the ideal source of a file without it: the same
// trajectory and the same electrical sums, bit for bit, through drive changes and phase faults.
TEST(OutputNetwork, DefaultsAndAnExplicitZeroNetworkGiveTheSameTrace) {
  const MotorParameters without = parse_motor_parameters(calibrated_text(), "li2019.toml");
  const MotorParameters zero = parse_motor_parameters(
      calibrated_text() + "\n[amplifier]\nsource_resistance_ohm = 0.0\nseries_inductance_uh = 0.0\n"
                          "parallel_inductance_uh = 0.0\n",
      "li2019+zero.toml");
  const MotorModel model_without(without), model_zero(zero);
  EXPECT_FALSE(model_zero.coefficients().effects.network);
  MotorSimulator a(model_without), b(model_zero);
  ElectricalSums sums_a, sums_b;
  for (const DriveInput& drive : {DriveInput{200.0, 40137.0, 90.0, 0.0}, DriveInput{320.0, 40300.0, -90.0, 1.0}}) {
    a.set_drive(drive);
    b.set_drive(drive);
    a.advance(30001, sums_a);
    b.advance(30001, sums_b);
  }
  ModelFaults faults;
  faults.phase_b_gain = 0.5;
  a.set_faults(faults);
  b.set_faults(faults);
  a.advance(5000);
  b.advance(5000);
  test::expect_same_state(a, b);
  EXPECT_EQ(sums_a.a_s, sums_b.a_s);
  EXPECT_EQ(sums_a.b_c, sums_b.b_c);
  EXPECT_EQ(sums_a.power_a, sums_b.power_a);
  EXPECT_EQ(a.network_gain_a(), Phasor(1.0, 0.0));
  EXPECT_EQ(b.network_divergence_count(), 0U);
}

// (d) The droop effect's gain, now the network's terminal voltage in magnitude, is the divider
// formula it had before: |V_cmd - R_s I_m| / |1 + j w R_s C0| / V_cmd, mean of the phases.
TEST(OutputNetwork, DroopGainKeepsItsMagnitude) {
  EffectCoefficients e;
  e.droop = true;
  e.source_resistance_ohm = 120.0;
  e.clamped_capacitance_f = 10e-9;
  e.charge_a_q1 = 0.31;
  e.charge_a_q2 = -0.12;
  e.charge_b_q1 = 0.08;
  e.charge_b_q2 = 0.27;
  const double w = 2.0 * kPi * 40100.0;
  const auto before = [&](double amplitude, double s, double c, Analytic q1, Analytic q2, double qa1, double qa2) {
    const double x = w * e.source_resistance_ohm * e.clamped_capacitance_f;
    const double re = amplitude * s + e.source_resistance_ohm * w * (qa1 * q1.im + qa2 * q2.im);
    const double im = -amplitude * c - e.source_resistance_ohm * w * (qa1 * q1.re + qa2 * q2.re);
    return std::sqrt(re * re + im * im) / amplitude / std::sqrt(1.0 + x * x);
  };
  for (const double theta : {0.0, 0.7, 2.9, -1.3}) {
    const double s = std::sin(theta), c = std::cos(theta);
    const Analytic q1{1.1e-6 * std::cos(theta + 0.2), 1.1e-6 * std::sin(theta + 0.2)};
    const Analytic q2{0.8e-6 * std::cos(theta - 1.1), 0.8e-6 * std::sin(theta - 1.1)};
    const double cp = 0.0, sp = 1.0;  // phase +90 deg: V_B = V0 cos(theta)
    const double expected = 0.5 *
                            (before(200.0, s, c, q1, q2, e.charge_a_q1, e.charge_a_q2) +
                             before(200.0, s * cp + c * sp, c * cp - s * sp, q1, q2, e.charge_b_q1, e.charge_b_q2));
    EXPECT_NEAR(droop_gain(e, w, s, c, cp, sp, 200.0, q1, q2), expected, 1e-14 * expected);
  }
  EXPECT_NEAR(droop_gain(e, w, 0.0, 1.0, 0.0, 1.0, 0.0, {}, {}), 1.0 / std::hypot(1.0, w * 120.0 * 10e-9),
              1e-15);  // no drive: the divider
}

// The droop effect alone stays the magnitude-only gain the SIMD lanes run; with an [amplifier]
// network its R_s joins the network's source resistance and the network carries it.
TEST(OutputNetwork, DroopAloneStaysMagnitudeOnlyAndJoinsANetwork) {
  MotorParameters p = test::calibrated_parameters();
  p.effects.amplifier_droop.enabled = true;
  p.effects.amplifier_droop.source_resistance_ohm = 60.0;
  const MotorModel droop(p);
  EXPECT_TRUE(droop.coefficients().effects.droop);
  EXPECT_FALSE(droop.coefficients().effects.network);
  EXPECT_TRUE(BatchSimulator::supports(droop));
  p.amplifier.parallel_inductance_uh = 1500.0;
  const MotorModel both(p);
  EXPECT_FALSE(both.coefficients().effects.droop);
  EXPECT_TRUE(both.coefficients().effects.network);
  EXPECT_EQ(both.coefficients().effects.output_network.source_resistance_ohm, 60.0);
  EXPECT_FALSE(BatchSimulator::supports(both));  // one amplitude per lane: the scalar path
}

// The envelope's implicit Euler settles on the circuit's steady state for any block: a known
// circuit, the motional current held.
TEST(OutputNetwork, EnvelopeSettlesOnTheSteadyState) {
  const OutputNetwork n{5.0, 1500e-6, 2000e-6, 10e-9};
  const double w = 2.0 * kPi * 40000.0;
  const Phasor source{100.0, 0.0}, motional{0.03, -0.01};
  NetworkPhase state;
  for (int i = 0; i < 20000; ++i) ASSERT_TRUE(step_network(n, w, 1.6e-6 * 64.0 / 48.0, source, motional, state));
  const Phasor expected = n.terminal_voltage_v(w, source, motional);
  EXPECT_NEAR(std::abs(state.gain * source - expected), 0.0, 1e-6 * std::abs(expected));
  // I_amp = Y_p V + I_m = (V_s - V)/Z_s.
  const Phasor amplifier = n.amplifier_current_a(w, expected, motional);
  EXPECT_NEAR(std::abs(amplifier - (source - expected) / n.series_impedance_ohm(w)), 0.0, 1e-9);
  EXPECT_NEAR(std::abs(state.series * source - amplifier), 0.0, 1e-6 * std::abs(amplifier));
}

// (e) A series inductance that resonates with C0 inside the motor's band behind no resistance is
// refused at load, one line naming the keys; a source resistance makes the same network usable.
TEST(OutputNetwork, DivergingNetworkIsRefusedWithOneLine) {
  const double l_s_uh = 1e6 / (std::pow(2.0 * kPi * 40000.0, 2) * 10e-9);  // resonates with C0 at 40 kHz
  const std::string text = calibrated_text() + "\n[amplifier]\nseries_inductance_uh = " + std::to_string(l_s_uh) + "\n";
  try {
    (void)parse_motor_parameters(text, "resonant.toml");
    FAIL() << "a lossless series resonance in the band was accepted";
  } catch (const ParameterError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find("resonant.toml"), std::string::npos) << message;
    EXPECT_NE(message.find("amplifier.series_inductance_uh"), std::string::npos) << message;
    EXPECT_NE(message.find("amplifier.source_resistance_ohm"), std::string::npos) << message;
    EXPECT_NE(message.find("stator.clamped_capacitance_nf"), std::string::npos) << message;
  }
  EXPECT_NO_THROW((void)parse_motor_parameters(text + "source_resistance_ohm = 5.0\n", "damped.toml"));
}

// At run time: a lossless network accepted at load (its resonance outside the band) driven at its
// resonance rings up; the blocks whose gain would pass the limit are counted, the step goes on.
TEST(OutputNetwork, RunTimeDivergenceIsCounted) {
  MotorParameters p = test::calibrated_parameters();
  const double f_resonance = 30000.0;  // below 0.9 x 39469 Hz
  // The phase's susceptance there (C0 and the modes' capacitive motional branch below their
  // resonance), from an ideal source: the series inductance that resonates with all of it.
  const MotorModel ideal(p);
  MotorSimulator probe(ideal);
  probe.set_drive({1.0, f_resonance, 90.0, 0.0});
  probe.advance(20000);
  ElectricalSums sums;
  probe.advance(20000, sums);
  const ElectricalReadings y = electrical_readings(sums, 90.0);
  const double w = 2.0 * kPi * f_resonance;
  const double b = y.current_a_a * std::sin(y.phase_a_deg * kPi / 180.0);  // at 1 V
  p.amplifier.series_inductance_uh = 1e6 / (w * b);
  const MotorModel model(p);
  MotorSimulator sim(model);
  sim.set_drive({1.0, f_resonance, 90.0, 0.0});
  sim.advance(static_cast<std::uint64_t>(0.05 / sim.time_step_s()));
  EXPECT_GT(sim.network_divergence_count(), 0U);
  EXPECT_LE(std::abs(sim.network_gain_a()), MotorSimulator::kLargestNetworkGain);
  EXPECT_FALSE(sim.diverged());
  // The same network at the motor's frequency stays bounded.
  MotorSimulator tuned(model);
  tuned.set_drive({100.0, 40137.0, 90.0, 0.0});
  tuned.advance(static_cast<std::uint64_t>(0.02 / tuned.time_step_s()));
  EXPECT_EQ(tuned.network_divergence_count(), 0U);
}

}  // namespace
}  // namespace swum
