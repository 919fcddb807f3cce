#include "model/modal/modal_constants.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "model/modal/geometry.h"
#include "model/modal/mode_shapes.h"
#include "model/motor_model.h"

namespace swum {
namespace {

constexpr double kPi = std::numbers::pi;

// Composite Simpson (independent of the Gauss-Legendre code under test).
template <typename F>
double simpson(F f, double a, double b, int n = 20000) {
  const double h = (b - a) / n;
  double s = f(a) + f(b);
  for (int i = 1; i < n; ++i) s += (i % 2 ? 4.0 : 2.0) * f(a + i * h);
  return s * h / 3.0;
}

void expect_rel(double actual, double expected, double rel, const char* what) {
  EXPECT_NEAR(actual, expected, std::abs(expected) * rel) << what;
}

TEST(Geometry, CalibrationReproducesModelSpecTable) {
  const StatorParameters s{};
  const auto g = calibrate_geometry(s);
  expect_rel(laminate_wave_speed_m_s(s), 4870.9, 1e-4, "cL");
  expect_rel(g.length_m, 61.632e-3, 1e-4, "L");
  expect_rel(g.half_height_m, 5.4314e-3, 1e-4, "hs");
  EXPECT_NEAR(2.0 * g.half_height_m / g.length_m, 0.17625, 1e-4);
}

TEST(ModalConstants, MatchModelSpecSection5Table) {
  const auto c = compute_modal_constants(MotorParameters{});
  expect_rel(c.substrate_area_m2, 5.540e-5, 1e-3, "As");
  expect_rel(c.patch_area_m2, 5.431e-6, 1e-3, "Ap");
  expect_rel(c.substrate_inertia_m4, 5.448e-10, 1e-3, "Is");
  expect_rel(c.m1_kg, 0.018490, 1e-4, "M1");
  expect_rel(c.k1_n_m, 1.13982e9, 1e-4, "K1");
  expect_rel(c.m2_kg, 0.036922, 1e-4, "M2");
  expect_rel(c.k2_n_m, 2.27069e9, 1e-4, "K2");
  expect_rel(c.alpha1, -0.112897, 1e-4, "alpha1");
  expect_rel(c.beta1_per_m, 6.7796, 1e-4, "beta1");
  expect_rel(c.beta2_per_m, 54.536, 1e-4, "beta2");
  EXPECT_DOUBLE_EQ(c.g_n, 2.0);
  expect_rel(c.g_t, 1.99845, 1e-5, "gT");
  expect_rel(c.a[0].group_a, 0.11297, 1e-4, "a0");
  expect_rel(c.b[0].group_a, -0.13191, 1e-4, "b0");
  expect_rel(c.a[1].group_a, -10.863, 1e-4, "a1");
  expect_rel(c.a[2].group_a, 0.86976, 1e-4, "a2");
  expect_rel(c.a[3].group_a, 869.76, 1e-4, "a3");
  expect_rel(c.a[4].group_a, -56.448, 1e-4, "a4");
  expect_rel(c.b[1].group_a, 12.683, 1e-4, "b1");
  expect_rel(c.b[2].group_a, 1.7327, 1e-4, "b2");
  expect_rel(c.b[3].group_a, 1732.7, 1e-4, "b3");
  expect_rel(c.b[4].group_a, 218.41, 1e-4, "b4");
  // Q factors of §5.
  EXPECT_NEAR(std::sqrt(c.k1_n_m * c.m1_kg) / c.c1_n_s_m, 117.7, 0.1);
  EXPECT_NEAR(std::sqrt(c.k2_n_m * c.m2_kg) / c.c2_n_s_m, 190.8, 0.1);
}

TEST(ModalConstants, MechanicalClosedForms) {
  const auto c = compute_modal_constants(MotorParameters{});
  const double L = c.geometry.length_m;
  const double ap = c.patch_area_m2;
  expect_rel(c.m1_kg, c.mass_per_length_kg_m * L / 2, 1e-12, "M1 = m_l L/2");
  expect_rel(c.alpha1, -8 * ap * kPi * kPi / (L * L), 1e-12, "alpha1");
  expect_rel(c.beta1_per_m, 3 * ap * std::pow(kPi, 4) / std::pow(L, 3), 1e-12, "beta1");
}

TEST(ModalConstants, ElectricalClosedFormsOfSection16) {
  const MotorParameters p{};
  const auto c = compute_modal_constants(p);
  const double L = c.geometry.length_m;
  const double hs = c.geometry.half_height_m;
  const double tp = c.geometry.piezo_thickness_m;
  const double e31 = p.stator.piezo_e31_c_m2;
  const ModeShapes m(L);
  const double j1l = m.phi_b_d1(L / 2) - m.phi_b_d1(0.0);
  const double j2 = simpson([&](double x) { return std::pow(m.phi_b_d2(x), 2); }, 0.0, L);
  const double j3l = simpson([&](double x) { return std::pow(m.phi_b_d2(x), 3); }, 0.0, L / 2);
  const double tol = 1e-8;
  // Group A coefficients (V_A); group B per the sign pattern of §1.6.
  expect_rel(c.a[0].group_a, -4 * e31 * hs, tol, "a0");
  expect_rel(c.a[1].group_a, -2 * hs / tp, tol, "a1");
  expect_rel(c.a[2].group_a, hs * kPi * kPi / L, tol, "a2");
  expect_rel(c.a[3].group_a, hs * kPi * kPi / (L * tp), tol, "a3");
  expect_rel(c.a[4].group_a, -4 * hs * kPi * kPi / (L * L), tol, "a4");
  for (int k = 0; k < 5; ++k) EXPECT_DOUBLE_EQ(c.a[k].group_a, c.a[k].group_b) << "a" << k;
  expect_rel(c.b[0].group_a, -2 * e31 * hs * hs * j1l, tol, "b0");
  expect_rel(c.b[1].group_a, -(hs * hs * j1l / tp), tol, "b1");
  expect_rel(c.b[2].group_a, 2.0 / 3.0 * hs * hs * hs * j2, tol, "b2");
  expect_rel(c.b[3].group_a, 2.0 / 3.0 * hs * hs * hs * j2 / tp, tol, "b3");
  expect_rel(c.b[4].group_a, -1.5 * std::pow(hs, 4) * j3l, tol, "b4");
  EXPECT_NEAR(c.b[0].group_b, -c.b[0].group_a, 1e-12);
  EXPECT_NEAR(c.b[1].group_b, -c.b[1].group_a, 1e-9);
  EXPECT_NEAR(c.b[2].group_b, c.b[2].group_a, 1e-12);
  EXPECT_NEAR(c.b[3].group_b, c.b[3].group_a, 1e-9);
  EXPECT_NEAR(c.b[4].group_b, -c.b[4].group_a, 1e-9);
}

TEST(ModalConstants, FrequenciesAndPreload) {
  const auto c = compute_modal_constants(MotorParameters{});
  EXPECT_NEAR(c.f_l1_hz, 39516.0, 39516.0 * 2e-3);
  EXPECT_NEAR(c.f_b2_hz, 39469.0, 39469.0 * 2e-3);
  EXPECT_NEAR(c.f_l1_full_contact_hz, 40400.0, 40.0);
  EXPECT_NEAR(c.static_q1_m, 41.6e-9, 0.1e-9);
  EXPECT_DOUBLE_EQ(c.drive_amplitude_per_volt, 1.0);  // the input is the terminal amplitude, on every motor
  EXPECT_DOUBLE_EQ(c.kappa_s_per_m, 3.6e6);
}

TEST(ModalConstants, SwitchableReadings) {
  const auto base = compute_modal_constants(MotorParameters{});
  MotorParameters p{};
  p.stator.tip_lever_over_length = 0.1321;
  EXPECT_NEAR(compute_modal_constants(p).g_t, 4.0734, 1e-3);
  EXPECT_NEAR(compute_modal_constants(p).g_tv, 4.0734, 1e-3);
  p.options.tip_velocity_lever = TipVelocityLever::free_tip;
  EXPECT_NEAR(compute_modal_constants(p).g_tv, base.phi_b_tip, 1e-12);

  MotorParameters x4{};
  x4.options.electrical_prefactors = ElectricalPrefactors::paper_x4;
  const auto c4 = compute_modal_constants(x4);
  EXPECT_DOUBLE_EQ(c4.a[0].group_a, base.a[0].group_a);
  for (int k = 1; k < 5; ++k) EXPECT_NEAR(c4.a[k].group_a, 4 * base.a[k].group_a, 1e-9 * std::abs(base.a[k].group_a));
  for (int k = 0; k < 5; ++k) EXPECT_DOUBLE_EQ(c4.b[k].group_a, base.b[k].group_a);

  MotorParameters swapped{};
  swapped.options.electrode_diagonals = ElectrodeDiagonals::swapped;
  const auto cs = compute_modal_constants(swapped);
  EXPECT_NEAR(cs.b[0].group_a, -base.b[0].group_a, 1e-12);
  EXPECT_NEAR(cs.a[0].group_a, base.a[0].group_a, 1e-12);

  // The input is the terminal amplitude whatever the paper's axis reads: one volt drives V0 = 1 V.
  EXPECT_DOUBLE_EQ(base.drive_amplitude_per_volt, 1.0);  // the default reads the paper peak-to-peak
  MotorParameters amplitude{};
  amplitude.options.paper_voltage_axis = PaperVoltageAxis::amplitude;
  EXPECT_DOUBLE_EQ(compute_modal_constants(amplitude).drive_amplitude_per_volt, 1.0);
  EXPECT_DOUBLE_EQ(amplitude_v_of_paper_voltage(PaperVoltageAxis::peak_to_peak, 400.0), 200.0);
  EXPECT_DOUBLE_EQ(amplitude_v_of_paper_voltage(PaperVoltageAxis::amplitude, 400.0), 400.0);
}

TEST(ModalConstants, ExplicitGeometryEqualsCalibratedWhenGivenSameSize) {
  MotorParameters p{};
  const auto cal = compute_modal_constants(p);
  p.stator.geometry = GeometryMode::explicit_size;
  p.stator.length_mm = cal.geometry.length_m * 1e3;
  p.stator.half_height_mm = cal.geometry.half_height_m * 1e3;
  const auto ex = compute_modal_constants(p);
  EXPECT_NEAR(ex.k2_n_m, cal.k2_n_m, 1e-9 * cal.k2_n_m);
  EXPECT_NEAR(ex.f_b2_hz, 39469.0, 1e-6);
}

TEST(MotorModel, LinearisedZeroesTheFourNonlinearConstants) {
  const auto lin = linearised(MotorParameters{});
  EXPECT_EQ(lin.stator.c111_pa, 0.0);
  EXPECT_EQ(lin.stator.c1111_pa, 0.0);
  EXPECT_EQ(lin.stator.e311_c_per_v_m, 0.0);
  EXPECT_EQ(lin.stator.e3111_c_per_v_m, 0.0);
  const MotorModel model(lin);
  EXPECT_EQ(model.coefficients().stator.l1.k3, 0.0);
  EXPECT_EQ(model.coefficients().stator.b2.sq1_a, 0.0);
  EXPECT_NEAR(model.constants().static_q1_m, 41.6e-9, 0.1e-9);
}

}  // namespace
}  // namespace swum
