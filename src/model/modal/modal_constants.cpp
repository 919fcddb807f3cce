#include "model/modal/modal_constants.h"

#include <cmath>
#include <numbers>

#include "model/modal/mode_shapes.h"
#include "model/modal/quadrature.h"

namespace swum {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// One electrode zone of a face (§1.6): x in [x0, x1], y in [y0, y1].
struct Zone {
  double x0, x1, y0, y1;
  bool group_a;
};

double y_moment(double y0, double y1, int n) { return (std::pow(y1, n + 1) - std::pow(y0, n + 1)) / (n + 1); }

// Static preload equilibrium of eq. 14 with V = 0:
// K1 q + c111 alpha1 q^2 + c1111 beta1 q^3 = gN max(0, F_P - k_e q) + gNP F_P.
double static_preload_q1(const ModalConstants& c, const MotorParameters& p) {
  const double fp = p.contact.preload_n;
  const double ke = p.contact.stiffness_n_m;
  const double k2 = p.stator.c111_pa * c.alpha1;
  const double k3 = p.stator.c1111_pa * c.beta1_per_m;
  double q = (c.g_n + c.g_np) * fp / (c.k1_n_m + c.g_n * ke);
  for (int it = 0; it < 50; ++it) {
    const bool contact = fp - ke * q > 0.0;
    const double r = c.k1_n_m * q + k2 * q * q + k3 * q * q * q - (contact ? c.g_n * (fp - ke * q) : 0.0) - c.g_np * fp;
    const double dr = c.k1_n_m + 2.0 * k2 * q + 3.0 * k3 * q * q + (contact ? c.g_n * ke : 0.0);
    const double dq = r / dr;
    q -= dq;
    if (std::abs(dq) <= 1e-16 * std::abs(q) + 1e-30) break;
  }
  return q;
}

}  // namespace

ModalConstants compute_modal_constants(const MotorParameters& p) {
  const auto& s = p.stator;
  ModalConstants c;
  c.geometry = stator_geometry(s);
  const double len = c.geometry.length_m;
  const double hs = c.geometry.half_height_m;
  const double ts = c.geometry.substrate_thickness_m;
  const double tp = c.geometry.piezo_thickness_m;
  const double hp = 2.0 * hs;
  c.wave_speed_m_s = laminate_wave_speed_m_s(s);

  // §1.1 sections.
  c.substrate_area_m2 = 2.0 * hs * ts;
  c.patch_area_m2 = hs * tp;
  c.substrate_inertia_m4 = 2.0 * ts * hs * hs * hs / 3.0;
  c.mass_per_length_kg_m = s.substrate_density_kg_m3 * c.substrate_area_m2 +
                           4.0 * s.piezo_density_kg_m3 * c.patch_area_m2;
  const double ap = c.patch_area_m2;

  const ModeShapes modes(len);
  const GaussLegendre gl(p.numerics.quadrature_points);
  // Integral over [0, L] as two intervals (the electrode split at L/2).
  auto over_beam = [&](auto&& f) { return gl.integrate(f, 0.0, 0.5 * len) + gl.integrate(f, 0.5 * len, len); };

  c.phi_b_tip = modes.phi_b(len);
  c.phi_b_slope_tip_per_m = modes.phi_b_d1(len);
  c.tip_lever_m = s.tip_lever_over_length * len;

  // Appendix A, mechanical.
  const double int_phil2 = over_beam([&](double x) { return std::pow(modes.phi_l(x), 2); });
  const double int_phib2 = over_beam([&](double x) { return std::pow(modes.phi_b(x), 2); });
  const double int_dphil2 = over_beam([&](double x) { return std::pow(modes.phi_l_d1(x), 2); });
  const double int_dphil3 = over_beam([&](double x) { return std::pow(modes.phi_l_d1(x), 3); });
  const double int_dphil4 = over_beam([&](double x) { return std::pow(modes.phi_l_d1(x), 4); });
  const double int_ddphib2 = over_beam([&](double x) { return std::pow(modes.phi_b_d2(x), 2); });
  const double int_ddphib4 = over_beam([&](double x) { return std::pow(modes.phi_b_d2(x), 4); });

  c.m1_kg = c.mass_per_length_kg_m * int_phil2;
  c.m2_kg = c.mass_per_length_kg_m * int_phib2;
  c.k1_n_m = (s.substrate_youngs_modulus_pa * c.substrate_area_m2 + 4.0 * s.piezo_c11_pa * ap) * int_dphil2;
  c.k2_n_m = (s.substrate_youngs_modulus_pa * c.substrate_inertia_m4 + s.piezo_c11_pa * hp * hp * ap / 3.0) *
             int_ddphib2;
  c.c1_n_s_m = s.damping_l1_n_s_m;
  c.c2_n_s_m = s.damping_b2_n_s_m;
  c.alpha1 = 6.0 * ap * int_dphil3;
  c.beta1_per_m = 8.0 * ap * int_dphil4;
  c.beta2_per_m = 0.1 * std::pow(hp, 4) * ap * int_ddphib4;
  if (p.contact.preload_application == PreloadApplication::both_ends) {
    c.g_n = modes.phi_l(0.0) - modes.phi_l(len);  // eq. 8: F_N at both ends
    c.g_np = 0.0;
  } else {
    c.g_n = -modes.phi_l(len);  // F_N(t) at the tip only
    c.g_np = modes.phi_l(0.0);  // constant F_P at the back end
  }
  c.g_t = c.phi_b_tip + c.tip_lever_m * c.phi_b_slope_tip_per_m;
  c.g_tv = p.options.tip_velocity_lever == TipVelocityLever::same_as_force ? c.g_t : c.phi_b_tip;

  // Appendix A, electrical (§1.5, layout §1.6): 8 zones = 2 faces x 4; E3 = V/tp.
  const bool standard = p.options.electrode_diagonals == ElectrodeDiagonals::standard;
  const Zone zones[4] = {
      {0.0, 0.5 * len, 0.0, hs, standard},    // 1 upper-left
      {0.5 * len, len, 0.0, hs, !standard},   // 2 upper-right
      {0.0, 0.5 * len, -hs, 0.0, !standard},  // 3 lower-left
      {0.5 * len, len, -hs, 0.0, standard},   // 4 lower-right
  };
  constexpr double kFaces = 2.0;
  // Sum_i Int E3^e y^n f(x) dV = Sum_i V_i^e tp^(1-e) Int y^n dy Int f dx.
  auto electrical = [&](int e_power, int y_power, auto&& f) {
    ElectricalCoefficient out;
    for (const auto& z : zones) {
      const double value = kFaces * std::pow(tp, 1 - e_power) * y_moment(z.y0, z.y1, y_power) *
                           gl.integrate(f, z.x0, z.x1);
      (z.group_a ? out.group_a : out.group_b) += value;
    }
    return out;
  };
  auto scaled = [](ElectricalCoefficient x, double k) { return ElectricalCoefficient{k * x.group_a, k * x.group_b}; };
  auto dphil = [&](int m) { return [&, m](double x) { return std::pow(modes.phi_l_d1(x), m); }; };
  auto ddphib = [&](int m) { return [&, m](double x) { return std::pow(modes.phi_b_d2(x), m); }; };
  const double x4 = p.options.electrical_prefactors == ElectricalPrefactors::paper_x4 ? 4.0 : 1.0;
  c.a[0] = scaled(electrical(1, 0, dphil(1)), s.piezo_e31_c_m2);
  c.a[1] = scaled(electrical(2, 0, dphil(1)), 0.5 * x4);
  c.a[2] = scaled(electrical(1, 0, dphil(2)), 1.0 * x4);
  c.a[3] = scaled(electrical(2, 0, dphil(2)), 1.0 * x4);
  c.a[4] = scaled(electrical(1, 0, dphil(3)), 1.5 * x4);
  c.b[0] = scaled(electrical(1, 1, ddphib(1)), -s.piezo_e31_c_m2);
  c.b[1] = scaled(electrical(2, 1, ddphib(1)), -0.5);
  c.b[2] = scaled(electrical(1, 2, ddphib(2)), 1.0);
  c.b[3] = scaled(electrical(2, 2, ddphib(2)), 1.0);
  c.b[4] = scaled(electrical(1, 3, ddphib(3)), -1.5);

  c.kappa_s_per_m = 3.6 * std::pow(10.0, p.contact.erf_steepness_exponent);
  c.drive_amplitude_per_volt = 1.0;  // inputs are terminal amplitudes (options.paper_voltage_axis reads the paper only)

  c.f_l1_hz = std::sqrt(c.k1_n_m / c.m1_kg) / kTwoPi;
  c.f_b2_hz = std::sqrt(c.k2_n_m / c.m2_kg) / kTwoPi;
  c.f_l1_full_contact_hz = std::sqrt((c.k1_n_m + c.g_n * p.contact.stiffness_n_m) / c.m1_kg) / kTwoPi;
  c.f_b2_stick_hz = std::sqrt((c.k2_n_m + c.g_t * c.g_tv * p.contact.tangential_stiffness_n_m) / c.m2_kg) / kTwoPi;
  c.static_q1_m = static_preload_q1(c, p);
  return c;
}

}  // namespace swum
