#include "analysis/sizing/series_in_loop.h"

#include <cmath>
#include <cstdint>
#include <exception>
#include <numbers>

#include "analysis/sizing/matching_network.h"
#include "model/machine/electrical.h"
#include "model/motor_model.h"
#include "model/simulation/simulator.h"

namespace swum {
namespace {

struct LoopState {
  bool ok = false;
  std::complex<double> admittance_siemens;  // phase A: terminal current / terminal voltage
  double terminal_a_v = 0.0, terminal_b_v = 0.0;
  double current_a_a = 0.0, current_phase_a_deg = 0.0;
};

// The steady state at the source amplitude: 0.1 s to settle (tens of the modes' and the network's
// time constants), then 128 housekeeping blocks (~170 periods) of the port's fit; the terminal
// voltage is the network's gain times the source.
LoopState run(const MotorModel& model, double source_v, double frequency_hz) {
  MotorSimulator sim(model);
  sim.set_drive({source_v, frequency_hz, 90.0, 0.0});
  sim.advance(static_cast<std::uint64_t>(0.1 / sim.time_step_s()) / 64 * 64);
  ElectricalSums sums;
  std::complex<double> gain_a, gain_b;
  constexpr int kBlocks = 128;
  for (int i = 0; i < kBlocks; ++i) {
    sim.advance(64, sums);
    gain_a += sim.network_gain_a() / double(kBlocks);
    gain_b += sim.network_gain_b() / double(kBlocks);
  }
  LoopState s;
  if (sim.diverged() || sim.network_divergence_count() > 0) return s;
  const ElectricalReadings e = electrical_readings(sums, 90.0);
  if (!e.valid) return s;
  // The port's current is referred to the source's phase; the terminal voltage is gain x source.
  const std::complex<double> current = admittance_from_reading(e.current_a_a, e.phase_a_deg, 1.0);
  s.admittance_siemens = current / (source_v * gain_a);
  s.terminal_a_v = std::abs(gain_a) * source_v;
  s.terminal_b_v = std::abs(gain_b) * source_v;
  s.current_a_a = std::abs(current);
  s.current_phase_a_deg = std::arg(current) * 180.0 / std::numbers::pi;
  s.ok = true;
  return s;
}

}  // namespace

SeriesInLoop series_matching_in_loop(const MotorParameters& ideal, double frequency_hz, double target_v,
                                     std::complex<double> admittance_siemens, double source_resistance_ohm,
                                     double tolerance, int max_rounds) {
  SeriesInLoop out;
  out.source_resistance_ohm = source_resistance_ohm;
  const double w = 2.0 * std::numbers::pi * frequency_hz;
  const double c0 = ideal.stator.clamped_capacitance_nf * 1e-9;
  std::complex<double> y = admittance_siemens;
  // The network's envelope takes the motional current from the linear coupling while the port's
  // admittance includes the non-linear terms: at 400 V on the default motor the design's fixed
  // point holds phase A 1.5 % low (393.9 V). Correcting the source voltage by the ratio on top
  // made the step-up (gain ~6) oscillate; the tolerance is the 2 %.
  for (int round = 1; round <= max_rounds; ++round) {
    out.rounds = round;
    SeriesMatching design;
    MotorParameters matched = ideal;
    try {
      design = series_matching({y, target_v, w, c0}, source_resistance_ohm);
      matched.amplifier.series_inductance_uh = design.inductance_h * 1e6;
      matched.amplifier.source_resistance_ohm = source_resistance_ohm;
      validate_parameters(matched, "the series design");
    } catch (const std::exception& e) {
      out.reason = e.what();
      return out;
    }
    const double source_v = design.amplifier_output_v;
    const LoopState s = run(MotorModel{matched}, source_v, frequency_hz);
    out.inductance_h = design.inductance_h;
    out.source_voltage_v = source_v;
    if (!s.ok) {
      out.reason = "the motor behind the series design diverged in the simulator";
      return out;
    }
    out.terminal_a_v = s.terminal_a_v;
    out.terminal_b_v = s.terminal_b_v;
    out.current_a_a = s.current_a_a;
    out.current_phase_a_deg = s.current_phase_a_deg;
    if (std::abs(s.terminal_a_v - target_v) <= tolerance * target_v) {
      out.converged = true;
      return out;
    }
    y = s.admittance_siemens;
  }
  out.reason = "no series design held the phase voltage within " + std::to_string(100.0 * tolerance) + " % after " +
               std::to_string(max_rounds) + " rounds";
  return out;
}

}  // namespace swum
