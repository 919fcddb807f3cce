// Parameters of the swum motor model (docs/model_spec.md §7, §5, §11) and the single table of
// parameter specifications used for validation, TOML parsing and docs/parameters.md.
#pragma once

#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace swum {

// Every validation / parse problem with a parameter set. The message names the source, the
// key (section.key), the line when known, what is wrong and the allowed range.
class ParameterError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// §5: how L and hs are obtained.
enum class GeometryMode {
  from_frequencies,  // L, hs from the target L1/B2 frequencies given ts, tp (calibrate_geometry)
  explicit_size,     // L, hs given directly (length_mm, half_height_mm)
};

// §11.1: how the paper's quoted voltages (its axis labelled "V") are read where the model is
// compared with the paper's figures (paper facts, validation curves, facts files). The model's
// input is always the terminal voltage amplitude of one phase, V0; this reading never changes it.
enum class PaperVoltageAxis {
  peak_to_peak,  // the paper's V is peak-to-peak: V0 = V/2 (paper: "peak-peak value")
  amplitude,     // the paper's V is the amplitude: V0 = V (the calibrated reading, §9.3)
};

// The terminal amplitude (V) that drives the model at a voltage the paper quotes.
[[nodiscard]] constexpr double amplitude_v_of_paper_voltage(PaperVoltageAxis axis, double paper_v) {
  return axis == PaperVoltageAxis::peak_to_peak ? 0.5 * paper_v : paper_v;
}

// §2.3 / §11.2: lever converting q2' into the tip velocity used by the friction law.
enum class TipVelocityLever {
  same_as_force,  // gTv = gT (passive interface)
  free_tip,       // gTv = phiB(L) (eq. 30)
};

// §1.5 / §11.5: prefactors of a1..a4.
enum class ElectricalPrefactors {
  derived,   // 1/2, 1, 1, 3/2 (from the energy of §1.4)
  paper_x4,  // 4x derived (the garbled Appendix A "2, 4, 4, 6")
};

// §1.6 / §11.6: which diagonal carries phase A.
enum class ElectrodeDiagonals {
  standard,  // phase A on zones {1,4,5,8}, phase B on {2,3,6,7}
  swapped,   // exchanged: reverses the direction of motion
};

// §10 / §11.8: friction treatment of the fixed-step solver.
enum class FrictionSolver {
  coulomb_projection,  // kappa -> infinity limit of the implicit erf solve
  erf_newton,          // exact root of the implicit erf equation (safeguarded Newton)
};

// How the preload reaches the L1 mode (eq. 8 / §2.1; calibration term, not in the paper).
enum class PreloadApplication {
  both_ends,          // paper eq. 8: F_N at both beam ends, generalised force gN F_N, gN = 2
  back_end_constant,  // constant F_P at the back end (soft preload spring), F_N(t) at the tip:
                      // generalised force phiL(0) F_P - phiL(L) F_N = F_P + F_N
};

// Linear-guide friction of the mover (eqs. 24-25, §11.9).
enum class GuideFrictionModel {
  smoothed_sign,     // literal eqs. 24-25 with sign(v_m) ~ tanh(v_m/w) (model_spec §11.9 default)
  implicit_coulomb,  // exact Coulomb mu_s (F_N + g m) with a stuck state, solved implicitly
                     // (projection); the reference ODE uses -f_g tanh(v_m/w) for it
};

// Table 1 + geometry (§5) + nonlinear constants (Table 2, reading of §7.2).
struct StatorParameters {
  double substrate_density_kg_m3 = 7850.0;
  double substrate_youngs_modulus_pa = 2.09e11;
  double piezo_density_kg_m3 = 7600.0;
  double piezo_c11_pa = 12.23e10;
  double piezo_e31_c_m2 = -5.2;
  double c111_pa = -1.4583e12;
  double c1111_pa = -2.8856e17;
  double e311_c_per_v_m = 3.3142e-6;
  double e3111_c_per_v_m = 6.4235e-3;
  double damping_l1_n_s_m = 39.0;
  double damping_b2_n_s_m = 48.0;
  double substrate_thickness_mm = 5.1;
  double piezo_thickness_mm = 1.0;
  GeometryMode geometry = GeometryMode::from_frequencies;
  double target_l1_frequency_hz = 39516.0;
  double target_b2_frequency_hz = 39469.0;
  double length_mm = 61.632;           // used only with geometry = explicit
  double half_height_mm = 5.4314;      // used only with geometry = explicit
  double tip_lever_over_length = 0.0;  // L1/L of §2.4: gT = phiB(L) + L1 phiB'(L)
  // Electrical port (electrical.h): the clamped (blocked) capacitance of one phase, the current
  // C0 dV/dt every amplifier sees besides the motional current. Not in the paper's model.
  double clamped_capacitance_nf = 10.0;
};

// Table 3, interface part (§2).
struct ContactParameters {
  double preload_n = 24.8;
  double stiffness_n_m = 2.58e7;
  double friction_coefficient = 0.35;   // mu_c
  double erf_steepness_exponent = 6.0;  // a: kappa = 3.6 * 10^a s/m (eq. 22)
  PreloadApplication preload_application = PreloadApplication::both_ends;
  // Jenkins element: tangential spring k_t in series with the Coulomb slider; 0 = rigid (paper).
  double tangential_stiffness_n_m = 0.0;
};

// Table 3, mover part (§3).
struct MoverParameters {
  double mass_kg = 0.2;
  double damping_n_s_m = 1.3;
  double guide_friction_coefficient = 0.04;  // mu_s
  double gravity_m_s2 = 9.81;
  double guide_sign_smoothing_m_s = 1.0e-4;  // sign(v) -> tanh(v/width); 0 = exact sign
  GuideFrictionModel guide_friction_model = GuideFrictionModel::smoothed_sign;
};

// The switchable readings of §11.
struct ModelOptions {
  PaperVoltageAxis paper_voltage_axis = PaperVoltageAxis::peak_to_peak;
  TipVelocityLever tip_velocity_lever = TipVelocityLever::same_as_force;
  ElectricalPrefactors electrical_prefactors = ElectricalPrefactors::derived;
  ElectrodeDiagonals electrode_diagonals = ElectrodeDiagonals::standard;
};

// How the simulator runs the fixed step of the Jenkins contact with the implicit Coulomb guide
// (the calibrated motor's): fused by hand into one loop (issue 16, ~1.4x faster) or through
// MotorSplitSystem's generic step; the results agree to rounding (tests/src/model/simulation/simulator_test).
// Other contact laws always run the generic step.
enum class StepKernel {
  fused,
  generic,
};

struct NumericsParameters {
  double time_step_ns = 1.0e9 / (96.0 * 40000.0);  // 96 steps per 40 kHz cycle (§10)
  FrictionSolver friction_solver = FrictionSolver::coulomb_projection;
  StepKernel step_kernel = StepKernel::fused;
  int quadrature_points = 400;                // Gauss-Legendre points per interval (§1.5)
  double divergence_limit_um = 1000.0;        // sqrt(q1^2 + q2^2) above this = runaway (NaN guard)
  double divergence_speed_limit_m_s = 100.0;  // |v_m| above this = runaway
};

// ---------------------------------------------------------------------------------------
// Candidate effects (docs/discrepancy.md): physical extensions the paper leaves out, each off
// by default. The defaults of the magnitudes are the documented default magnitudes of
// `swum synth --effect NAME`. One free parameter each (the first member after `enabled`);
// the others are fixed physical constants so that the effect stays identifiable.

// Non-linear electroelasticity added to the configured constants:
// c111 += scale * c111_ref, ... with the reference Table-2 values of config/li2019.toml
// (a linear baseline thus becomes scale x the calibrated non-linear stator).
struct ElectroelasticEffect {
  bool enabled = false;
  double scale = 1.0;
};

// Stator temperature rise T (K over ambient): dT/dt = (R_th P - T)/tau, P = mean of
// C1 q1'^2 + C2 q2'^2 (modal damping power, eqs. 14-15). K_i -> K_i (1 + a_K T),
// C_i -> C_i (1 + a_C T) (the paper's named missing effect, Sec. 5).
struct ThermalEffect {
  bool enabled = false;
  double thermal_resistance_k_per_w = 4.0;       // free: R_th
  double time_constant_s = 30.0;                 // fixed: tau
  double stiffness_coefficient_per_k = -2.0e-4;  // fixed: a_K (PZT-8 c11, steel E ~ -2e-4/K)
  double damping_coefficient_per_k = 5.0e-3;     // fixed: a_C (Qm of PZT-8 drops with T)
};

// Friction pair wear: mu_c(s) = mu_c (1 + d (1 - exp(-s/s0))), s = mover travel (sliding)
// distance accumulated since the start of the session.
struct WearEffect {
  bool enabled = false;
  double friction_change = 0.3;     // free: d (relative change of mu_c after run-in; + = wear roughens)
  double run_in_distance_m = 20.0;  // fixed: s0
};

// Preload error: F_P -> f F_P and, for a Hertzian contact (k ~ F^(1/3)), k_e -> f^(1/3) k_e.
struct PreloadEffect {
  bool enabled = false;
  double preload_factor = 0.8;  // free: f
};

// Extra linear-guide friction: mu_s -> mu_s + d (widens the dead zone, eq. 24).
struct GuideFrictionEffect {
  bool enabled = false;
  double extra_coefficient = 0.05;  // free: d
};

// Amplifier source impedance: per phase V = (V_cmd - R_s I_m)/(1 + j w R_s C0), I_m the
// motional current a0 q1' + b0 q2' (reciprocity of the linear coupling of eqs. 14-15);
// applied to the drive amplitude. C0 is the stator's clamped capacitance
// (StatorParameters::clamped_capacitance_nf): the same capacitance of the same phase the
// electrical port sees, one value for both.
struct AmplifierDroopEffect {
  bool enabled = false;
  double source_resistance_ohm = 60.0;  // free: R_s
};

// The amplifier's output network, the same on both phases (docs/amplifier.md): the source
// behind R_s + j w L_s, an optional inductor L_p across each phase. All zero: an ideal source,
// the terminal voltage is the commanded one (the network is not evaluated).
struct AmplifierParameters {
  double source_resistance_ohm = 0.0;
  double series_inductance_uh = 0.0;    // 0 = none
  double parallel_inductance_uh = 0.0;  // 0 = no parallel inductor
};

struct EffectParameters {
  ElectroelasticEffect electroelastic;
  ThermalEffect thermal;
  WearEffect wear;
  PreloadEffect preload;
  GuideFrictionEffect guide_friction;
  AmplifierDroopEffect amplifier_droop;
};

struct MotorParameters {
  StatorParameters stator;
  ContactParameters contact;
  MoverParameters mover;
  ModelOptions options;
  NumericsParameters numerics;
  EffectParameters effects;
  AmplifierParameters amplifier;
};

// The reference Table-2 constants the electroelastic effect scales (config/li2019.toml).
struct ReferenceNonlinearConstants {
  double c111_pa = -1.4583e12;
  double c1111_pa = -0.85e17;
  double e311_c_per_v_m = 3.3142e-6;
  double e3111_c_per_v_m = 6.4235e-3;
};

// The parameters the constant model is built from: the electroelastic, preload and
// guide-friction effects folded into stator/contact/mover (the slow and fast effects,
// thermal, wear and amplifier droop, act inside the simulator).
[[nodiscard]] MotorParameters with_static_effects(MotorParameters parameters);

// The linear variant: the four nonlinear constants c111, c1111, e311, e3111 set to zero.
[[nodiscard]] MotorParameters linearised(MotorParameters parameters);

// ---------------------------------------------------------------------------------------
// The parameter table.
enum class ParameterKind { real, integer, boolean, choice };

struct ParameterSpec {
  std::string_view section;  // TOML table
  std::string_view key;      // TOML key (unit in the name, or in `unit`)
  std::string_view unit;
  std::string_view description;
  ParameterKind kind;
  double min_value;                           // inclusive (real/integer)
  double max_value;                           // inclusive (real/integer)
  std::span<const std::string_view> choices;  // kind == choice: names, index = enum value
  double (*get)(const MotorParameters&);      // bool -> 0/1, choice -> index
  void (*set)(MotorParameters&, double);

  // "section.key" (e.g. "effects.thermal.time_constant_s").
  [[nodiscard]] std::string name() const;
};

// All parameters, in documentation order.
[[nodiscard]] std::span<const ParameterSpec> parameter_specs();

// Looks up "section.key"; nullptr if unknown.
[[nodiscard]] const ParameterSpec* find_parameter_spec(std::string_view section, std::string_view key);

// The sections of the table in its order, for messages: "stator, contact, mover, ...".
[[nodiscard]] std::string parameter_section_names();

// Checks every value against its spec (finite, in range, valid choice). Throws ParameterError
// naming source_name and the first offending key.
void validate_parameters(const MotorParameters& parameters, std::string_view source_name);

// Text of a value as it would be written in TOML (choices as quoted names).
[[nodiscard]] std::string format_parameter_value(const ParameterSpec& spec, double value);

// "text" (with double quotes).
[[nodiscard]] std::string quoted(std::string_view text);

// docs/parameters.md, rendered from the table (defaults = MotorParameters{}).
[[nodiscard]] std::string render_parameters_markdown();

}  // namespace swum
