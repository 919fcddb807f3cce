// The Butterworth-Van Dyke (BVD) equivalent circuit of one phase (docs/model.md, "Equivalent
// circuit"): the clamped capacitance C0 in parallel with one series motional R_m-L_m-C_m branch
// per mode (the subscript m for motional; L1 and B2 are the modes).
// From the linear part of eqs. 14-15 and the electrical port (electrical.h): a phase X drives
// mode i with the force N V_X (N = lin0, the linear modal force per volt, N/V = C/m) and the
// mode's velocity returns the motional current N q_i' (reciprocity), so with
// M_i q'' + C_i q' + K_i q = N V:
//   I/V = j w C0 + sum_i N^2 / (C_i + j w M_i + K_i/(j w)),
// i.e. R_m = C_i/N^2, L_m = M_i/N^2, C_m = N^2/K_i.
#pragma once

#include <array>
#include <complex>

#include "analysis/admittance/admittance_measurement.h"
#include "model/motor_model.h"

namespace swum {

struct MotionalBranch {
  double resistance_ohm = 0.0;  // R_m
  double inductance_h = 0.0;    // L_m
  double capacitance_f = 0.0;   // C_m
};

// Index 0 = L1 mode, 1 = B2 mode.
inline constexpr std::size_t kCircuitModes = 2;

struct EquivalentCircuit {
  double clamped_capacitance_f = 0.0;  // C0
  std::array<MotionalBranch, kCircuitModes> branches{};
};

// Series resonance fs = 1/(2 pi sqrt(L_m C_m)) (the branch's impedance is real: R_m).
[[nodiscard]] double series_resonance_hz(const MotionalBranch& branch);
// Parallel (anti-)resonance of the branch with C0 alone: fp = fs sqrt(1 + C_m/C0).
[[nodiscard]] double parallel_resonance_hz(const MotionalBranch& branch, double clamped_capacitance_f);
// Effective coupling factor k_eff^2 = (fp^2 - fs^2)/fp^2, which for this circuit equals
// C_m/(C0 + C_m) exactly.
[[nodiscard]] double coupling_factor_squared(const MotionalBranch& branch, double clamped_capacitance_f);
// Mechanical quality factor Q = 2 pi fs L_m / R_m (= sqrt(K M)/C of the mode).
[[nodiscard]] double quality_factor(const MotionalBranch& branch);

// Y(f) of the circuit (S).
[[nodiscard]] std::complex<double> circuit_admittance_siemens(const EquivalentCircuit& circuit, double frequency_hz);

// The circuit that follows from the modal constants of `model` for the driven phase: N = lin0
// of that phase for each mode (StatorForceCoefficients), M_i, K_i, C_i, and C0 =
// clamped_capacitance_nf. Free: exact for the linear free stator (no contact, small signal).
// Assembled: the small-signal circuit with the tip held on the mover (in contact, sticking):
// the contact springs add to the modal stiffnesses, K1 + gN k_e and K2 + gT gTv k_t (the
// frequencies f_l1_full_contact_hz and f_b2_stick_hz of ModalConstants); R_m and L_m are the
// free stator's. `model` is the mounted one (mounted_parameters).
[[nodiscard]] EquivalentCircuit analytic_equivalent_circuit(const MotorModel& model, DrivenPhase phase,
                                                            Mounting mounting = Mounting::free);

}  // namespace swum
