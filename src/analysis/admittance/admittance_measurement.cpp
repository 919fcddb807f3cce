#include "analysis/admittance/admittance_measurement.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

#include "model/machine/electrical.h"
#include "model/motor_model.h"
#include "model/simulation/model_faults.h"
#include "model/simulation/simulator.h"

namespace swum {

std::string_view driven_phase_name(DrivenPhase phase) { return phase == DrivenPhase::a ? "a" : "b"; }

std::string_view mounting_name(Mounting mounting) { return mounting == Mounting::free ? "free" : "assembled"; }

MotorParameters mounted_parameters(MotorParameters parameters, Mounting mounting) {
  if (mounting == Mounting::free) {
    parameters.contact.preload_n = 0.0;
    parameters.contact.stiffness_n_m = 0.0;
    parameters.effects.preload.enabled = false;  // it scales F_P and k_e, both 0 here
  }
  parameters.effects.amplifier_droop.enabled = false;
  return parameters;
}

double longest_modal_time_constant_s(const MotorParameters& parameters) {
  const MotorModel model(parameters);
  const ModalConstants& c = model.constants();
  return std::max(2.0 * c.m1_kg / c.c1_n_s_m, 2.0 * c.m2_kg / c.c2_n_s_m);
}

namespace {

void check_options(const AdmittanceSweepOptions& o) {
  if (o.frequencies_hz.empty()) throw std::invalid_argument("admittance: the frequency grid is empty");
  for (double f : o.frequencies_hz) {
    if (!(std::isfinite(f) && f > 0.0)) throw std::invalid_argument("admittance: frequencies must be > 0 Hz");
  }
  if (!(std::isfinite(o.amplitude_v) && o.amplitude_v > 0.0))
    throw std::invalid_argument("admittance: the amplitude must be > 0 V");
  if (!(std::isfinite(o.first_settle_time_constants) && std::isfinite(o.settle_time_constants) &&
        o.first_settle_time_constants >= 0.0 && o.settle_time_constants >= 0.0 && o.window_periods >= 1))
    throw std::invalid_argument("admittance: settle times must be >= 0 and the window at least one period");
}

// Steps of `seconds` (finite, >= 0, checked with the sweep's total against the cap first).
std::uint64_t steps_for(double seconds, double dt) {
  return static_cast<std::uint64_t>(std::ceil(std::max(0.0, seconds) / dt));
}

std::string general(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// The time constant must be finite and the whole sweep within kMaxAdmittanceSweepSteps, checked
// in floating point before any count is cast to an integer.
void check_duration(const MotorParameters& p, const AdmittanceSweepOptions& o, double tau_s, double dt) {
  const std::string damping = "stator.damping_l1_n_s_m = " + general(p.stator.damping_l1_n_s_m) +
                              ", damping_b2_n_s_m = " + general(p.stator.damping_b2_n_s_m);
  if (!(std::isfinite(tau_s) && tau_s > 0.0))
    throw std::invalid_argument("admittance: the modal damping (" + damping +
                                ") gives no finite time constant 2M/C to settle for; it must be > 0");
  double steps = o.first_settle_time_constants * tau_s / dt;
  for (double f : o.frequencies_hz) steps += o.settle_time_constants * tau_s / dt + o.window_periods / f / dt;
  if (!(steps <= kMaxAdmittanceSweepSteps))
    throw std::invalid_argument(
        "admittance: " + std::to_string(o.frequencies_hz.size()) + " points need " + general(steps) +
        " simulator steps, over the cap of " + general(kMaxAdmittanceSweepSteps) + ": the modal damping (" + damping +
        ") makes the settle time constant 2M/C " + general(tau_s) + " s; raise the damping or use fewer points");
}

}  // namespace

std::vector<AdmittancePoint> measure_admittance(const MotorParameters& parameters, const AdmittanceSweepOptions& o) {
  check_options(o);
  const MotorParameters mounted = mounted_parameters(parameters, o.mounting);
  const MotorModel model(mounted);
  const double tau_s = longest_modal_time_constant_s(mounted);
  const double dt = model.time_step_s();
  check_duration(mounted, o, tau_s, dt);

  MotorSimulator sim(model);
  ModelFaults faults;
  (o.phase == DrivenPhase::a ? faults.phase_b_gain : faults.phase_a_gain) = 0.0;
  sim.set_faults(faults);
  sim.set_slow_states(0.0, 0.0, true);  // an analyser's sweep is too short to heat the stator

  std::vector<std::size_t> order(o.frequencies_hz.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t i, std::size_t j) { return o.frequencies_hz[i] > o.frequencies_hz[j]; });

  std::vector<AdmittancePoint> out(o.frequencies_hz.size());
  const double rad = std::numbers::pi / 180.0;
  bool first = true;
  for (std::size_t index : order) {
    const double f = o.frequencies_hz[index];
    DriveInput drive;
    drive.amplitude_v = o.amplitude_v;
    drive.frequency_hz = f;
    drive.phase_deg = 90.0;
    sim.set_drive(drive);
    sim.clear_diverged();
    sim.advance(steps_for((first ? o.first_settle_time_constants : o.settle_time_constants) * tau_s, dt));
    first = false;
    ElectricalSums sums;
    sim.advance(steps_for(o.window_periods / f, dt), sums);
    const ElectricalReadings r = electrical_readings(sums, drive.phase_deg);
    AdmittancePoint& p = out[index];
    p.frequency_hz = f;
    p.amplitude_v = o.amplitude_v;
    p.current_a = o.phase == DrivenPhase::a ? r.current_a_a : r.current_b_a;
    p.phase_deg = o.phase == DrivenPhase::a ? r.phase_a_deg : r.phase_b_deg;
    p.magnitude_siemens = p.current_a / o.amplitude_v;
    p.conductance_siemens = p.magnitude_siemens * std::cos(p.phase_deg * rad);
    p.susceptance_siemens = p.magnitude_siemens * std::sin(p.phase_deg * rad);
    p.diverged = sim.diverged() || !r.valid;
  }
  return out;
}

}  // namespace swum
