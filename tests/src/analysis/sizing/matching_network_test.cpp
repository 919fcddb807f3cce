// The matching network's formulas (src/analysis/sizing/matching_network.h) on their own, and in
// the time-domain simulator: the sized network, set as [amplifier] on the default motor, does at
// the design point what the formulas promise (docs/amplifier.md, issue 36).
#include "analysis/sizing/matching_network.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#include "analysis/operating_point/operating_band.h"
#include "analysis/sizing/amplifier_sizing.h"
#include "calibrated_parameters.h"
#include "model/motor_model.h"
#include "model/simulation/simulator.h"

namespace swum {
namespace {

constexpr double kPi = std::numbers::pi;

// The formulas against a circuit whose answer is known: C0 in parallel with a resistor.
TEST(MatchingNetwork, FormulasCancelTheSusceptanceOfAKnownCircuit) {
  const double w = 2.0 * kPi * 40000.0, c0 = 10e-9, g = 1.0 / 2000.0;
  const MatchingDesignPoint point{{g, w * c0}, 200.0, w, c0};
  // (a) and (b) coincide when C0 is the whole susceptance; L resonates with C0 at w.
  const double l_c0 = c0_compensating_inductance_h(w, c0);
  EXPECT_NEAR(1.0 / std::sqrt(l_c0 * c0), w, 1e-9 * w);
  const ParallelMatching parallel = parallel_matching(point);
  EXPECT_NEAR(parallel.inductance_h, l_c0, 1e-12 * l_c0);
  EXPECT_NEAR(parallel.amplifier_current_a, g * 200.0, 1e-12);  // the resistor's current alone
  // (c) The series inductance makes the total impedance real, R_s + R: the amplifier's voltage
  // over that divider gives the target.
  const SeriesMatching series = series_matching(point, 5.0);
  const std::complex<double> y = point.admittance_siemens;
  const std::complex<double> z_total = std::complex<double>{5.0, w * series.inductance_h} + 1.0 / y;
  EXPECT_NEAR(z_total.imag(), 0.0, 1e-9 * std::abs(z_total));
  const std::complex<double> current = series.amplifier_output_v / z_total;
  EXPECT_NEAR(std::abs(current / y), 200.0, 1e-9 * 200.0);  // terminal voltage = I / Y
  EXPECT_NEAR(std::abs(current), series.amplifier_current_a, 1e-12);
  // An inductive phase admits neither network: one-line errors.
  const MatchingDesignPoint inductive{{g, -w * c0}, 200.0, w, c0};
  EXPECT_THROW((void)parallel_matching(inductive), std::invalid_argument);
  EXPECT_THROW((void)series_matching(inductive), std::invalid_argument);
}

// The design point of the default motor: 200 V at `swum pick --config config/li2019.toml
// --amplitude-v 200`'s drift-aware frequency for 0 N.
constexpr double kDesignAmplitudeV = 200.0;
constexpr double kDesignFrequencyHz = 40137.0;

// Phase A in the simulator's steady state at the design frequency: its admittance Y = I/V from
// the amplifier's measurement of its outputs (advance(steps, ElectricalSums&): the current's
// fundamental referred to theta, the source's phase) and the terminal voltage the network makes
// (network_gain_a: V/V_s), and the amplifier's readings averaged over the window's blocks.
struct PhaseAState {
  std::complex<double> admittance_siemens;
  AmplifierPhaseReadings readings;  // the mean over the window's blocks
};

PhaseAState measure_phase_a(const MotorModel& model, double source_amplitude_v,
                            double frequency_hz = kDesignFrequencyHz) {
  MotorSimulator sim(model);
  sim.set_drive({source_amplitude_v, frequency_hz, 90.0, 0.0});
  const double dt = sim.time_step_s();
  sim.advance(static_cast<std::uint64_t>(0.1 / dt) / 64 * 64);
  ElectricalSums sums;
  constexpr int kBlocks = 128;  // ~170 drive periods
  std::complex<double> gain;
  PhaseAState out;
  for (int i = 0; i < kBlocks; ++i) {
    sim.advance(64, sums);
    gain += sim.network_gain_a() / double(kBlocks);
    const AmplifierPhaseReadings r = sim.amplifier_readings().a;
    out.readings.current_a += r.current_a / kBlocks;
    out.readings.current_phase_deg += r.current_phase_deg / kBlocks;
    out.readings.terminal_amplitude_v += r.terminal_amplitude_v / kBlocks;
    out.readings.terminal_phase_deg += r.terminal_phase_deg / kBlocks;
  }
  EXPECT_EQ(sim.network_divergence_count(), 0U);
  const ElectricalReadings e = electrical_readings(sums, 90.0);
  out.admittance_siemens = admittance_from_reading(e.current_a_a, e.phase_a_deg, 1.0) / (source_amplitude_v * gain);
  return out;
}

// (b) With the parallel inductance that cancels phase A's susceptance at the design point, the
// amplifier's current of phase A is in phase with its voltage (within 5 deg) in the time-domain
// simulator, and its amplitude is G V; without the inductor it leads by far more (C0's current).
TEST(MatchingNetwork, ParallelInductanceBringsTheAmplifierCurrentInPhaseInTheSimulator) {
  const MotorParameters ideal = test::calibrated_parameters();
  const PhaseAState design = measure_phase_a(MotorModel{ideal}, kDesignAmplitudeV);
  const double w = 2.0 * kPi * kDesignFrequencyHz;
  const double c0 = ideal.stator.clamped_capacitance_nf * 1e-9;
  const ParallelMatching parallel = parallel_matching({design.admittance_siemens, kDesignAmplitudeV, w, c0});
  EXPECT_GT(design.readings.current_phase_deg, 45.0);  // the ideal source: C0's current dominates
  MotorParameters matched = ideal;
  matched.amplifier.parallel_inductance_uh = parallel.inductance_h * 1e6;
  const PhaseAState with = measure_phase_a(MotorModel{matched}, kDesignAmplitudeV);
  EXPECT_NEAR(with.readings.current_phase_deg, 0.0, 5.0);
  EXPECT_NEAR(with.readings.current_a, parallel.amplifier_current_a, 0.05 * parallel.amplifier_current_a);
  EXPECT_NEAR(with.readings.terminal_amplitude_v, kDesignAmplitudeV, 1e-9 * kDesignAmplitudeV);  // Z_s = 0
  std::printf("design Y_A = %.4g %+.4gj S; L_p = %.1f uH; phase %.2f deg -> %.2f deg; I_amp %.4f A (G V %.4f A)\n",
              design.admittance_siemens.real(), design.admittance_siemens.imag(), parallel.inductance_h * 1e6,
              design.readings.current_phase_deg, with.readings.current_phase_deg, with.readings.current_a,
              parallel.amplifier_current_a);
}

// (c) Series matching: L_s and the amplifier voltage from phase A's admittance bring phase A's
// terminal voltage to the target within 2 %. The same network is on phase B, whose admittance
// differs: it shifts B's voltage otherwise than A's, the motor's state moves, and so does phase
// A's admittance, to which a series-matched phase (Q ~ 6) is sensitive. The design is therefore
// repeated on the admittance of the state it makes until it holds (docs/amplifier.md).
TEST(MatchingNetwork, SeriesMatchingReachesTheTargetPhaseVoltageInTheSimulator) {
  const MotorParameters ideal = test::calibrated_parameters();
  const double w = 2.0 * kPi * kDesignFrequencyHz;
  const double c0 = ideal.stator.clamped_capacitance_nf * 1e-9;
  const double r_s = 5.0;  // a real amplifier's output resistance: R_s = 0 is refused at load
  std::complex<double> y = measure_phase_a(MotorModel{ideal}, kDesignAmplitudeV).admittance_siemens;
  double terminal_v = 0.0;
  for (int round = 0; round < 10; ++round) {
    const SeriesMatching series = series_matching({y, kDesignAmplitudeV, w, c0}, r_s);
    MotorParameters matched = ideal;
    matched.amplifier.series_inductance_uh = series.inductance_h * 1e6;
    matched.amplifier.source_resistance_ohm = r_s;
    const PhaseAState state = measure_phase_a(MotorModel{matched}, series.amplifier_output_v);
    terminal_v = state.readings.terminal_amplitude_v;
    std::printf("round %d: L_s = %.1f uH, V_s = %.2f V, I = %.4f A -> V_A %.1f V, I_amp %.4f A at %.1f deg\n", round,
                series.inductance_h * 1e6, series.amplifier_output_v, series.amplifier_current_a, terminal_v,
                state.readings.current_a, state.readings.current_phase_deg);
    if (std::abs(terminal_v - kDesignAmplitudeV) < 0.02 * kDesignAmplitudeV) break;
    y = state.admittance_siemens;
  }
  EXPECT_NEAR(terminal_v, kDesignAmplitudeV, 0.02 * kDesignAmplitudeV);
}

// The same with what `swum size` buys: its parallel inductor of phase A, sized at its design row
// (the highest voltage, unloaded, from the down-sweep's interpolated figures), set as [amplifier]
// and run in the time-domain simulator at that row's frequency and voltage.
TEST(MatchingNetwork, TheParallelInductorSwumSizeBuysHoldsTheAmplifierCurrentInPhaseAtItsDesignRow) {
  const MotorParameters ideal = test::calibrated_parameters();
  BandGrid grid;
  grid.voltages = {200.0, 400.0};
  for (double f = 41000.0; f >= 39000.0; f -= 25.0) grid.frequencies_hz.push_back(f);
  const std::vector<BandRow> rows = operating_band(MotorModel{ideal}, grid, serial_for, 1);
  const SizingResult sizing = size_amplifier(rows, ideal.stator.clamped_capacitance_nf * 1e-9,
                                             default_design_row(rows));
  ASSERT_TRUE(sizing.designed);
  ASSERT_TRUE(sizing.design_a.parallel_ok) << sizing.design_a.parallel_reason;
  const SizingRow& design = sizing.rows[sizing.design_row];
  ASSERT_EQ(design.amplitude_v, 400.0);
  const PhaseAState without = measure_phase_a(MotorModel{ideal}, 400.0, design.frequency_hz);
  MotorParameters matched = ideal;
  matched.amplifier.parallel_inductance_uh = sizing.design_a.parallel_inductance_h * 1e6;
  const PhaseAState with = measure_phase_a(MotorModel{matched}, 400.0, design.frequency_hz);
  // The amplifier's current as its output's fundamental: the phase's terminal current fitted over
  // the window (the port, non-linear coupling included) plus the inductor's V/(j w L_p); the
  // terminal voltage is the source's (Z_s = 0).
  const double w = 2.0 * kPi * design.frequency_hz;
  const std::complex<double> amplifier = parallel_amplifier_current(with.admittance_siemens, w, 400.0,
                                                                    sizing.design_a.parallel_inductance_h);
  const double phase_deg = std::arg(amplifier) * 180.0 / kPi;
  std::printf("swum size's design row: 400 V at %.1f Hz, L_p = %.1f uH; phase A's amplifier current %.2f deg -> "
              "%.2f deg, %.4f A (size: %.4f A); MotorSimulator::amplifier_readings (linear motional current) %.2f "
              "deg\n",
              design.frequency_hz, sizing.design_a.parallel_inductance_h * 1e6, without.readings.current_phase_deg,
              phase_deg, std::abs(amplifier), sizing.design_a.parallel_current_amplitude_a,
              with.readings.current_phase_deg);
  EXPECT_GT(without.readings.current_phase_deg, 45.0);
  EXPECT_NEAR(phase_deg, 0.0, 5.0);
  EXPECT_NEAR(std::abs(amplifier), sizing.design_a.parallel_current_amplitude_a,
              0.05 * sizing.design_a.parallel_current_amplitude_a);
}

}  // namespace
}  // namespace swum
