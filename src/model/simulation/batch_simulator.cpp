// BatchSimulator: the step of MotorSimulator (simulator.cpp, motor.h) in SIMD lanes over
// operating points. Compiled once per Highway target (foreach_target.h) and dispatched at run
// time to the best one the CPU has (HWY_DYNAMIC_DISPATCH).
#include "model/simulation/batch_simulator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "hwy/aligned_allocator.h"
#include "model/machine/motor.h"
#include "model/simulation/simulator.h"

// foreach_target.h includes this file once per target: what is not per target is compiled once.
#ifndef SWUM_BATCH_SIMULATOR_SHARED
#define SWUM_BATCH_SIMULATOR_SHARED
namespace swum {

// Fields of the structure of arrays, each `padded` doubles long.
enum BatchField : std::size_t {
  kQ1,
  kQ2,
  kXm,
  kV1,
  kV2,
  kVm,
  kDelta,
  kSin,
  kCos,
  kTime,
  kAmplitude,
  kCosPhase,
  kSinPhase,
  kRotationCos,
  kRotationSin,
  kLoad,
  kNormal,
  kFriction,
  kGuide,
  kUMin,
  kUMax,
  kWMin,
  kWMax,
  kContact,
  kFrictionSum,
  kFrictionSqSum,
  kNormalSum,
  kPowerSum,
  kDivergedFlag,
  kDivergedCount,
  // Per-lane model constants that the frozen slow states of thermal and wear change
  // (MotorSplitSystem::set_modal_factors / set_friction_coefficient), and those states.
  kLaneK1,
  kLaneK2,
  kLaneC1,
  kLaneC2,
  kLaneA1,
  kLaneA2,
  kLaneInverseCompliance,
  kLaneDtGtOverM2,
  kLaneFriction,
  kLaneSlider,
  kLaneTemperature,
  kLaneDistance,
  // Amplifier droop: the commanded amplitude V0 and the gain at the piezo (kAmplitude = V0 gain).
  kLaneCommandedAmplitude,
  kLaneDroopGain,
  kLaneAngularFrequency,
  // The interface's power balance (WindowStatistics::add_interface).
  kSlipSum,
  kMoverSum,
  // The electrical port (ElectricalSums, in its order): 1 / (2 cos(w dt/2)) for the midpoint
  // phasor, then the sums of the lane's samples.
  kLaneMidpointScale,
  kElecSamples,
  kElecSS,
  kElecCC,
  kElecSC,
  kElecAS,
  kElecAC,
  kElecBS,
  kElecBC,
  kElecMAS,
  kElecMAC,
  kElecMBS,
  kElecMBC,
  kElecPowerA,
  kElecPowerB,
  kElecASq,
  kElecBSq,
  kElecAPeak,
  kElecBPeak,
  kElecVAS,
  kElecVAC,
  kElecVBS,
  kElecVBC,
  kElecVASq,
  kElecVBSq,
  kFieldCount
};

// Everything the step reads that is the same in every lane (broadcast in the kernel).
struct BatchConstants {
  ModeForceCoefficients l1, b2;
  double a1 = 0.0, a2 = 0.0;  // step-corrected inverse masses (MotorSplitSystem::update_step)
  double c1 = 0.0, c2 = 0.0, g_n = 0.0, g_t = 0.0, g_tv = 0.0, preload_constant = 0.0;
  double clamped_capacitance = 0.0;  // C0 of one phase (electrical.h)
  double preload = 0.0, contact_stiffness = 0.0, friction_coefficient = 0.0;
  double tangential_stiffness = 0.0, slider_limit_per_normal = 0.0;
  double inverse_compliance = 0.0, dt_g_t_over_m2 = 0.0, dt_over_m = 0.0, m_over_dt = 0.0, dt_mu_s_over_m = 0.0;
  double mover_mass_inv = 0.0, mover_damping = 0.0;
  double guide_coefficient = 0.0, guide_weight = 0.0, guide_inverse_width = 0.0;
  double dt = 0.0;
  double position_limit_sq = 0.0, speed_limit_sq = 0.0;
  double rest_q1 = 0.0;
  bool jenkins = false;
  bool coulomb_guide = true;
  bool per_lane = false;  // thermal or wear: the lanes' slow states set some constants per lane
};

struct BatchSimulator::Arrays {
  hwy::AlignedFreeUniquePtr<double[]> data;
  std::vector<unsigned char> group_active;    // per kLanePadding lanes: any lane not idle
  std::vector<unsigned char> group_sampling;  // per kLanePadding lanes: any lane sampling
  std::vector<unsigned char> lane_sampling;
  std::vector<unsigned char> lane_idle;
  BatchConstants k;
};

}  // namespace swum
#endif  // SWUM_BATCH_SIMULATOR_SHARED

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "model/simulation/batch_simulator.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace swum {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;

// modal_force_n (stator.h) of one mode in every lane.
HWY_INLINE V ModalForce(D d, const ModeForceCoefficients& m, V stiffness, V q, V va, V vb, V va2, V vb2) {
  const V c0 = hn::MulAdd(hn::Set(d, m.sq0_b), vb2,
                          hn::MulAdd(hn::Set(d, m.sq0_a), va2,
                                     hn::MulAdd(hn::Set(d, m.lin0_b), vb, hn::Mul(hn::Set(d, m.lin0_a), va))));
  const V c1 = hn::Sub(hn::MulAdd(hn::Set(d, m.sq1_b), vb2,
                                  hn::MulAdd(hn::Set(d, m.sq1_a), va2,
                                             hn::MulAdd(hn::Set(d, m.lin1_b), vb, hn::Mul(hn::Set(d, m.lin1_a), va)))),
                       stiffness);
  const V c2 = hn::Sub(hn::MulAdd(hn::Set(d, m.lin2_b), vb, hn::Mul(hn::Set(d, m.lin2_a), va)), hn::Set(d, m.k2));
  return hn::MulAdd(q, hn::MulAdd(q, hn::NegMulAdd(hn::Set(d, m.k3), q, c2), c1), c0);
}

// clamp(x, -limit, limit) for limit >= 0 (the scalar `x > l ? l : (x < -l ? -l : x)`).
HWY_INLINE V Clamp(V x, V limit) { return hn::Min(hn::Max(x, hn::Neg(limit)), limit); }

// clamped_tanh (mover.h) in every lane: the Pade approximant, clamped at +-1 and replaced by
// +-1 beyond |x| > 4.97 (x = 0 gives 0 from the formula itself).
HWY_INLINE V ClampedTanh(D d, V x) {
  const V x2 = hn::Mul(x, x);
  const V num = hn::Mul(x, hn::MulAdd(x2, hn::MulAdd(x2, hn::Add(x2, hn::Set(d, 378.0)), hn::Set(d, 17325.0)),
                                      hn::Set(d, 135135.0)));
  const V den = hn::MulAdd(x2,
                           hn::MulAdd(x2, hn::MulAdd(hn::Set(d, 28.0), x2, hn::Set(d, 3150.0)), hn::Set(d, 62370.0)),
                           hn::Set(d, 135135.0));
  const V one = hn::Set(d, 1.0);
  const V t = hn::Min(hn::Max(hn::Div(num, den), hn::Neg(one)), one);
  const V big = hn::Set(d, 4.97);
  return hn::IfThenElse(hn::Gt(x, big), one, hn::IfThenElse(hn::Lt(x, hn::Neg(big)), hn::Neg(one), t));
}

// The electrical port's sample of one step in every lane (simulator_loop.h sample_electrical with
// phase_currents, electrical.h, and ElectricalSums::add, in their order): at the step's midpoint,
// (s, c) from the phasors at its start and end, q the mean of the start and end, v the end's.
HWY_INLINE void SampleElectrical(D d, const BatchConstants& k, double* HWY_RESTRICT base, std::size_t padded,
                                 std::size_t i, V s_start, V c_start, V s_end, V c_end, V q1_mid, V q2_mid, V v1,
                                 V v2) {
  auto f = [&](std::size_t field) { return base + field * padded + i; };
  auto accumulate = [&](std::size_t field, V x) { hn::Store(hn::Add(hn::Load(d, f(field)), x), d, f(field)); };
  const V scale = hn::Load(d, f(kLaneMidpointScale));
  const V s = hn::Mul(hn::Add(s_start, s_end), scale);
  const V c = hn::Mul(hn::Add(c_start, c_end), scale);
  const V amp = hn::Load(d, f(kAmplitude));
  const V cph = hn::Load(d, f(kCosPhase)), sph = hn::Load(d, f(kSinPhase));
  const V omega_amp = hn::Mul(hn::Load(d, f(kLaneAngularFrequency)), amp);
  const V va = hn::Mul(amp, s);
  const V vb = hn::Mul(amp, hn::MulAdd(s, cph, hn::Mul(c, sph)));
  const V dva = hn::Mul(omega_amp, c);
  const V dvb = hn::Mul(omega_amp, hn::MulSub(c, cph, hn::Mul(s, sph)));
  const V two = hn::Set(d, 2.0);
  // One mode's share of the motional current of phase X: (df/dV_X) v + (d^2W/dV_X^2) V_X'.
  auto share = [&](V q, V v, double lin0, double sq0, double lin1, double sq1, double lin2, V vx, V dvx) {
    const V df = hn::MulAdd(
        q, hn::MulAdd(hn::Set(d, lin2), q, hn::MulAdd(hn::Mul(two, hn::Set(d, sq1)), vx, hn::Set(d, lin1))),
        hn::MulAdd(hn::Mul(two, hn::Set(d, sq0)), vx, hn::Set(d, lin0)));
    const V cap = hn::Mul(q, hn::MulAdd(hn::Set(d, sq1), q, hn::Mul(two, hn::Set(d, sq0))));
    return hn::MulAdd(df, v, hn::Mul(cap, dvx));
  };
  const ModeForceCoefficients& l1 = k.l1;
  const ModeForceCoefficients& b2 = k.b2;
  const V ma = hn::Add(share(q1_mid, v1, l1.lin0_a, l1.sq0_a, l1.lin1_a, l1.sq1_a, l1.lin2_a, va, dva),
                       share(q2_mid, v2, b2.lin0_a, b2.sq0_a, b2.lin1_a, b2.sq1_a, b2.lin2_a, va, dva));
  const V mb = hn::Add(share(q1_mid, v1, l1.lin0_b, l1.sq0_b, l1.lin1_b, l1.sq1_b, l1.lin2_b, vb, dvb),
                       share(q2_mid, v2, b2.lin0_b, b2.sq0_b, b2.lin1_b, b2.sq1_b, b2.lin2_b, vb, dvb));
  const V c0 = hn::Set(d, k.clamped_capacitance);
  const V ia = hn::MulAdd(c0, dva, ma);
  const V ib = hn::MulAdd(c0, dvb, mb);
  accumulate(kElecSamples, hn::Set(d, 1.0));
  accumulate(kElecSS, hn::Mul(s, s));
  accumulate(kElecCC, hn::Mul(c, c));
  accumulate(kElecSC, hn::Mul(s, c));
  accumulate(kElecAS, hn::Mul(ia, s));
  accumulate(kElecAC, hn::Mul(ia, c));
  accumulate(kElecBS, hn::Mul(ib, s));
  accumulate(kElecBC, hn::Mul(ib, c));
  accumulate(kElecMAS, hn::Mul(ma, s));
  accumulate(kElecMAC, hn::Mul(ma, c));
  accumulate(kElecMBS, hn::Mul(mb, s));
  accumulate(kElecMBC, hn::Mul(mb, c));
  accumulate(kElecPowerA, hn::Mul(va, ma));
  accumulate(kElecPowerB, hn::Mul(vb, mb));
  accumulate(kElecASq, hn::Mul(ia, ia));
  accumulate(kElecBSq, hn::Mul(ib, ib));
  hn::Store(hn::Max(hn::Load(d, f(kElecAPeak)), hn::Abs(ia)), d, f(kElecAPeak));
  hn::Store(hn::Max(hn::Load(d, f(kElecBPeak)), hn::Abs(ib)), d, f(kElecBPeak));
  accumulate(kElecVAS, hn::Mul(va, s));
  accumulate(kElecVAC, hn::Mul(va, c));
  accumulate(kElecVBS, hn::Mul(vb, s));
  accumulate(kElecVBC, hn::Mul(vb, c));
  accumulate(kElecVASq, hn::Mul(va, va));
  accumulate(kElecVBSq, hn::Mul(vb, vb));
}

// kPerLane: the constants of the slow states are per lane (thermal or wear), else broadcast.
// group_sampling: per kLanePadding lanes, whether to sample the electrical port (every
// MotorSimulator::kElectricalStride-th step of the clock, as MotorSimulator).
template <bool kJenkins, bool kCoulombGuide, bool kPerLane>
HWY_NOINLINE void AdvanceLanes(const BatchConstants& k, double* HWY_RESTRICT base, std::size_t padded,
                               const unsigned char* group_active, const unsigned char* group_sampling,
                               std::uint64_t steps, std::uint64_t clock) {
  const D d;
  const std::size_t n = hn::Lanes(d);
  auto f = [&](std::size_t field) { return base + field * padded; };
  double* HWY_RESTRICT q1p = f(kQ1);
  double* HWY_RESTRICT q2p = f(kQ2);
  double* HWY_RESTRICT xmp = f(kXm);
  double* HWY_RESTRICT v1p = f(kV1);
  double* HWY_RESTRICT v2p = f(kV2);
  double* HWY_RESTRICT vmp = f(kVm);
  double* HWY_RESTRICT dlp = f(kDelta);
  double* HWY_RESTRICT sp = f(kSin);
  double* HWY_RESTRICT cp = f(kCos);
  double* HWY_RESTRICT tp = f(kTime);
  const double* HWY_RESTRICT ampp = f(kAmplitude);
  const double* HWY_RESTRICT cphp = f(kCosPhase);
  const double* HWY_RESTRICT sphp = f(kSinPhase);
  const double* HWY_RESTRICT rcp = f(kRotationCos);
  const double* HWY_RESTRICT rsp = f(kRotationSin);
  const double* HWY_RESTRICT loadp = f(kLoad);
  double* HWY_RESTRICT fnp = f(kNormal);
  double* HWY_RESTRICT ftp = f(kFriction);
  double* HWY_RESTRICT ffp = f(kGuide);
  double* HWY_RESTRICT uminp = f(kUMin);
  double* HWY_RESTRICT umaxp = f(kUMax);
  double* HWY_RESTRICT wminp = f(kWMin);
  double* HWY_RESTRICT wmaxp = f(kWMax);
  double* HWY_RESTRICT contactp = f(kContact);
  double* HWY_RESTRICT ftsp = f(kFrictionSum);
  double* HWY_RESTRICT ft2p = f(kFrictionSqSum);
  double* HWY_RESTRICT fnsp = f(kNormalSum);
  double* HWY_RESTRICT powp = f(kPowerSum);
  double* HWY_RESTRICT divflagp = f(kDivergedFlag);
  double* HWY_RESTRICT divcountp = f(kDivergedCount);

  const V zero = hn::Zero(d);
  const V one = hn::Set(d, 1.0);
  const V dt = hn::Set(d, k.dt);
  const V a1_all = hn::Set(d, k.a1), a2_all = hn::Set(d, k.a2);
  const V c1_all = hn::Set(d, k.c1), c2_all = hn::Set(d, k.c2);
  const V k1_all = hn::Set(d, k.l1.k), k2_all = hn::Set(d, k.b2.k);
  const V g_n = hn::Set(d, k.g_n), g_tv = hn::Set(d, k.g_tv), pc = hn::Set(d, k.preload_constant);
  const V g_t = hn::Set(d, k.g_t);
  double* HWY_RESTRICT slipp = f(kSlipSum);
  double* HWY_RESTRICT moverp = f(kMoverSum);
  constexpr std::uint64_t kStride = MotorSimulator::kElectricalStride;
  const V preload = hn::Set(d, k.preload), ke = hn::Set(d, k.contact_stiffness);
  const V mu_all = hn::Set(d, k.friction_coefficient);
  const V kt = hn::Set(d, k.tangential_stiffness), slider_all = hn::Set(d, k.slider_limit_per_normal);
  const V inv_compliance_all = hn::Set(d, k.inverse_compliance);
  const V dt_gt_m2_all = hn::Set(d, k.dt_g_t_over_m2), dt_m = hn::Set(d, k.dt_over_m), m_dt = hn::Set(d, k.m_over_dt);
  const V dt_mus_m = hn::Set(d, k.dt_mu_s_over_m);
  const V minv = hn::Set(d, k.mover_mass_inv), cm = hn::Set(d, k.mover_damping);
  const V mus = hn::Set(d, k.guide_coefficient), weight = hn::Set(d, k.guide_weight);
  const V inv_width = hn::Set(d, k.guide_inverse_width);
  const V pos_lim2 = hn::Set(d, k.position_limit_sq), speed_lim2 = hn::Set(d, k.speed_limit_sq);
  const V rest_q1 = hn::Set(d, k.rest_q1);
  const V tiny = hn::Set(d, 1e-200);

  for (std::uint64_t step = 0; step < steps; ++step) {
    const bool housekeeping = ((++clock) & 63U) == 0U;
    const bool electrical_step = (clock & (kStride - 1)) == 0U;
    for (std::size_t i = 0; i < padded; i += n) {
      if (group_active[i / BatchSimulator::kLanePadding] == 0U) continue;
      V q1 = hn::Load(d, q1p + i), q2 = hn::Load(d, q2p + i), xm = hn::Load(d, xmp + i);
      V v1 = hn::Load(d, v1p + i), v2 = hn::Load(d, v2p + i), vm = hn::Load(d, vmp + i);
      V s = hn::Load(d, sp + i), c = hn::Load(d, cp + i);
      const V a1 = kPerLane ? hn::Load(d, f(kLaneA1) + i) : a1_all;
      const V a2 = kPerLane ? hn::Load(d, f(kLaneA2) + i) : a2_all;
      const V c1 = kPerLane ? hn::Load(d, f(kLaneC1) + i) : c1_all;
      const V c2 = kPerLane ? hn::Load(d, f(kLaneC2) + i) : c2_all;
      const V k1 = kPerLane ? hn::Load(d, f(kLaneK1) + i) : k1_all;
      const V k2 = kPerLane ? hn::Load(d, f(kLaneK2) + i) : k2_all;
      const V mu = kPerLane ? hn::Load(d, f(kLaneFriction) + i) : mu_all;
      const V slider = kPerLane ? hn::Load(d, f(kLaneSlider) + i) : slider_all;
      const V inv_compliance = kPerLane ? hn::Load(d, f(kLaneInverseCompliance) + i) : inv_compliance_all;
      const V dt_gt_m2 = kPerLane ? hn::Load(d, f(kLaneDtGtOverM2) + i) : dt_gt_m2_all;
      const V amp = hn::Load(d, ampp + i);
      const V load = hn::Load(d, loadp + i);
      // Drive voltages (drive.h).
      const V va = hn::Mul(amp, s);
      const V vb = hn::Mul(amp, hn::MulAdd(s, hn::Load(d, cphp + i), hn::Mul(c, hn::Load(d, sphp + i))));
      // explicit_acceleration (motor.h): F_N = max(0, F_P - k_e q1), modal forces, damping.
      const V fn = hn::Max(hn::NegMulAdd(ke, q1, preload), zero);
      const V va2 = hn::Mul(va, va), vb2 = hn::Mul(vb, vb);
      const V f1 = ModalForce(d, k.l1, k1, q1, va, vb, va2, vb2);
      const V f2 = ModalForce(d, k.b2, k2, q2, va, vb, va2, vb2);
      const V acc1 = hn::Mul(a1, hn::NegMulAdd(c1, v1, hn::Add(hn::MulAdd(g_n, fn, f1), pc)));
      const V acc2 = hn::Mul(a2, hn::NegMulAdd(c2, v2, f2));
      const V acc3 = hn::Mul(minv, hn::NegMulAdd(cm, vm, hn::Neg(load)));
      const V w1 = hn::MulAdd(dt, acc1, v1);
      V w2 = hn::MulAdd(dt, acc2, v2);
      V w3 = hn::MulAdd(dt, acc3, vm);
      // implicit_velocity_correction: tangential contact clamped to the cone mu_c F_N.
      const V limit = hn::Mul(mu, fn);
      V ft;
      V delta;
      if constexpr (kJenkins) {
        // Projected onto the cone first, as the scalar step (MotorSplitSystem, advance_jenkins):
        // a no-op unless a lane starts outside it (set_lane with another preload or mu_c).
        delta = Clamp(hn::Load(d, dlp + i), hn::Mul(slider, fn));
        ft = Clamp(hn::Mul(kt, delta), limit);
      } else {
        ft = Clamp(hn::Mul(hn::MulSub(g_tv, w2, w3), inv_compliance), limit);
      }
      w2 = hn::NegMulAdd(dt_gt_m2, ft, w2);
      V ff;
      if constexpr (kCoulombGuide) {
        const V v_pred = hn::MulAdd(dt_m, ft, w3);
        const V cap = hn::Mul(dt_mus_m, hn::Add(fn, weight));
        w3 = hn::IfThenElse(hn::Gt(v_pred, cap), hn::Sub(v_pred, cap),
                            hn::IfThenElseZero(hn::Lt(v_pred, hn::Neg(cap)), hn::Add(v_pred, cap)));
        ff = hn::Mul(hn::Sub(w3, v_pred), m_dt);
      } else {
        // guide_friction_n (mover.h), eqs. 24-25, at the velocity of the start of the step.
        const V sign = ClampedTanh(d, hn::Mul(vm, inv_width));
        const V f_max = hn::Mul(sign, hn::Mul(mus, hn::Add(fn, weight)));
        const auto stuck = hn::Lt(hn::Abs(ft), hn::Add(hn::Abs(f_max), load));
        ff = hn::IfThenElse(stuck, hn::Sub(load, ft), hn::Neg(f_max));
        w3 = hn::MulAdd(dt_m, hn::Add(ft, ff), w3);
      }
      if constexpr (kJenkins) {
        // Return mapping with F_N at the end of the step.
        const V q1_next = hn::MulAdd(dt, w1, q1);
        const V fn_next = hn::Max(hn::NegMulAdd(ke, q1_next, preload), zero);
        delta = Clamp(hn::MulAdd(dt, hn::MulSub(g_tv, w2, w3), delta), hn::Mul(slider, fn_next));
      }
      // Semi-implicit Euler (semi_implicit_euler.h): v = v*, q += dt v.
      const V q1_start = q1, q2_start = q2, s_start = s, c_start = c;
      v1 = w1;
      v2 = w2;
      vm = w3;
      q1 = hn::MulAdd(dt, v1, q1);
      q2 = hn::MulAdd(dt, v2, q2);
      xm = hn::MulAdd(dt, vm, xm);
      // Drive phasor (rotate_phasor) and time.
      const V rc = hn::Load(d, rcp + i), rs = hn::Load(d, rsp + i);
      const V s_next = hn::MulAdd(s, rc, hn::Mul(c, rs));
      c = hn::NegMulAdd(s, rs, hn::Mul(c, rc));
      s = s_next;
      if (electrical_step && group_sampling[i / BatchSimulator::kLanePadding] != 0U) {
        const V half = hn::Set(d, 0.5);
        SampleElectrical(d, k, base, padded, i, s_start, c_start, s, c, hn::Mul(half, hn::Add(q1_start, q1)),
                         hn::Mul(half, hn::Add(q2_start, q2)), v1, v2);
      }
      const V t = hn::Add(hn::Load(d, tp + i), dt);
      if (housekeeping) {
        // renormalise_phasor, flush_tiny (simulator.cpp).
        const V r = hn::NegMulAdd(hn::Set(d, 0.5), hn::MulAdd(s, s, hn::Mul(c, c)), hn::Set(d, 1.5));
        s = hn::Mul(s, r);
        c = hn::Mul(c, r);
        v1 = hn::IfThenZeroElse(hn::Lt(hn::Abs(v1), tiny), v1);
        v2 = hn::IfThenZeroElse(hn::Lt(hn::Abs(v2), tiny), v2);
        vm = hn::IfThenZeroElse(hn::Lt(hn::Abs(vm), tiny), vm);
      }
      // NaN / runaway guard: a lane that fails it restarts at rest; the others are untouched.
      const V sum = hn::Add(hn::Add(v1, v2), xm);
      const auto sane = hn::And(hn::And(hn::Lt(hn::MulAdd(q1, q1, hn::Mul(q2, q2)), pos_lim2),
                                        hn::Lt(hn::Mul(vm, vm), speed_lim2)),
                                hn::Eq(hn::Sub(sum, sum), zero));
      if (!hn::AllTrue(d, sane)) [[unlikely]] {
        q1 = hn::IfThenElse(sane, q1, rest_q1);
        q2 = hn::IfThenElseZero(sane, q2);
        xm = hn::IfThenElseZero(sane, xm);
        v1 = hn::IfThenElseZero(sane, v1);
        v2 = hn::IfThenElseZero(sane, v2);
        vm = hn::IfThenElseZero(sane, vm);
        if constexpr (kJenkins) delta = hn::IfThenElseZero(sane, delta);
        hn::Store(hn::IfThenElse(sane, hn::Load(d, divflagp + i), one), d, divflagp + i);
        hn::Store(hn::Add(hn::Load(d, divcountp + i), hn::IfThenZeroElse(sane, one)), d, divcountp + i);
      }
      if constexpr (kJenkins) hn::Store(delta, d, dlp + i);
      hn::Store(q1, d, q1p + i);
      hn::Store(q2, d, q2p + i);
      hn::Store(xm, d, xmp + i);
      hn::Store(v1, d, v1p + i);
      hn::Store(v2, d, v2p + i);
      hn::Store(vm, d, vmp + i);
      hn::Store(s, d, sp + i);
      hn::Store(c, d, cp + i);
      hn::Store(t, d, tp + i);
      hn::Store(fn, d, fnp + i);
      hn::Store(ft, d, ftp + i);
      hn::Store(ff, d, ffp + i);
      // Window sums (steady_state.cpp WindowStats::add) after the step.
      const V u = hn::Neg(q1);
      const V w = hn::Mul(g_tv, q2);
      hn::Store(hn::Min(hn::Load(d, uminp + i), u), d, uminp + i);
      hn::Store(hn::Max(hn::Load(d, umaxp + i), u), d, umaxp + i);
      hn::Store(hn::Min(hn::Load(d, wminp + i), w), d, wminp + i);
      hn::Store(hn::Max(hn::Load(d, wmaxp + i), w), d, wmaxp + i);
      hn::Store(hn::Add(hn::Load(d, contactp + i), hn::IfThenElseZero(hn::Gt(fn, zero), dt)), d, contactp + i);
      hn::Store(hn::MulAdd(dt, ft, hn::Load(d, ftsp + i)), d, ftsp + i);
      hn::Store(hn::MulAdd(hn::Mul(dt, ft), ft, hn::Load(d, ft2p + i)), d, ft2p + i);
      hn::Store(hn::MulAdd(dt, fn, hn::Load(d, fnsp + i)), d, fnsp + i);
      const V power = hn::MulAdd(hn::Mul(c2, v2), v2, hn::Mul(hn::Mul(c1, v1), v1));
      hn::Store(hn::MulAdd(dt, power, hn::Load(d, powp + i)), d, powp + i);
      const V impulse = hn::Mul(dt, ft);
      hn::Store(hn::MulAdd(impulse, hn::MulSub(g_t, v2, vm), hn::Load(d, slipp + i)), d, slipp + i);
      hn::Store(hn::MulAdd(impulse, vm, hn::Load(d, moverp + i)), d, moverp + i);
    }
  }
}

template <bool kPerLane>
void AdvanceBatchWith(const BatchConstants& k, double* base, std::size_t padded, const unsigned char* group_active,
                      const unsigned char* group_sampling, std::uint64_t steps, std::uint64_t clock) {
  const unsigned char* ga = group_active;
  const unsigned char* gs = group_sampling;
  if (k.jenkins) {
    if (k.coulomb_guide) return AdvanceLanes<true, true, kPerLane>(k, base, padded, ga, gs, steps, clock);
    return AdvanceLanes<true, false, kPerLane>(k, base, padded, ga, gs, steps, clock);
  }
  if (k.coulomb_guide) return AdvanceLanes<false, true, kPerLane>(k, base, padded, ga, gs, steps, clock);
  return AdvanceLanes<false, false, kPerLane>(k, base, padded, ga, gs, steps, clock);
}

void AdvanceBatch(const BatchConstants& k, double* base, std::size_t padded, const unsigned char* group_active,
                  const unsigned char* group_sampling, std::uint64_t steps, std::uint64_t clock) {
  if (k.per_lane) return AdvanceBatchWith<true>(k, base, padded, group_active, group_sampling, steps, clock);
  return AdvanceBatchWith<false>(k, base, padded, group_active, group_sampling, steps, clock);
}

const char* LaneTargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace swum
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace swum {

HWY_EXPORT(AdvanceBatch);
HWY_EXPORT(LaneTargetName);

const char* BatchSimulator::simd_target() { return HWY_DYNAMIC_DISPATCH(LaneTargetName)(); }

namespace {

std::int64_t restricted_target = 0;  // restrict_simd_target's choice; 0: none

// The targets compiled in that the CPU runs, whatever restrict_simd_target chose.
std::vector<std::int64_t> cpu_targets() {
  hwy::SetSupportedTargetsForTest(0);
  std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
  hwy::SetSupportedTargetsForTest(restricted_target);
  return targets;
}

}  // namespace

std::vector<std::string> BatchSimulator::available_simd_targets() {
  std::vector<std::string> names;
  for (const std::int64_t target : cpu_targets()) names.emplace_back(hwy::TargetName(target));
  return names;
}

bool BatchSimulator::restrict_simd_target(const std::string& name) {
  std::int64_t chosen = 0;
  for (const std::int64_t target : cpu_targets()) {
    if (name == hwy::TargetName(target)) chosen = target;
  }
  if (chosen == 0 && !name.empty()) return false;
  restricted_target = chosen;
  hwy::SetSupportedTargetsForTest(restricted_target);
  hwy::GetChosenTarget().Update(hwy::SupportedTargets());
  return true;
}

namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();
}

bool BatchSimulator::supports(const MotorModel& model) {
  const MotorCoefficients& k = model.coefficients();
  const bool guide_in_lanes = k.guide_model == GuideFrictionModel::implicit_coulomb ||
                              k.guide.inverse_sign_width_s_m > 0.0;
  // The [amplifier] output network shifts each phase's voltage: not in the lanes' one amplitude.
  return k.tangential != TangentialContact::rigid_erf && guide_in_lanes && !k.effects.network;
}

BatchSimulator::BatchSimulator(const MotorModel& model, std::size_t lanes)
    : model_(model),
      lanes_(std::max<std::size_t>(lanes, 1)),
      padded_((std::max<std::size_t>(lanes, 1) + kLanePadding - 1) / kLanePadding * kLanePadding),
      dt_(model.time_step_s()),
      a_(std::make_unique<Arrays>()) {
  if (!supports(model)) {
    throw std::invalid_argument("BatchSimulator: the erf friction root and the exact-sign guide are not in lanes");
  }
  a_->data = hwy::AllocateAligned<double>(kFieldCount * padded_);
  std::fill_n(a_->data.get(), kFieldCount * padded_, 0.0);
  a_->group_active.assign(padded_ / kLanePadding, 0U);
  a_->group_sampling.assign(padded_ / kLanePadding, 0U);
  a_->lane_sampling.assign(padded_, 0U);
  a_->lane_idle.assign(padded_, 1U);
  const MotorCoefficients& c = model.coefficients();
  const MotorSplitSystem system(c, dt_);
  const MotorSplitSystem::StepConstants s = system.step_constants();
  BatchConstants& k = a_->k;
  k.l1 = c.stator.l1;
  k.b2 = c.stator.b2;
  k.a1 = s.a1_per_kg;
  k.a2 = s.a2_per_kg;
  k.c1 = c.c1_n_s_m;
  k.c2 = c.c2_n_s_m;
  k.g_n = c.g_n;
  k.g_t = c.g_t;
  k.g_tv = c.g_tv;
  k.clamped_capacitance = c.clamped_capacitance_f;
  k.preload_constant = c.preload_constant_force_n;
  k.preload = c.preload_n;
  k.contact_stiffness = c.contact_stiffness_n_m;
  k.friction_coefficient = c.friction_coefficient;
  k.tangential_stiffness = c.tangential_stiffness_n_m;
  k.slider_limit_per_normal = c.slider_limit_per_normal_force_m_n;
  k.inverse_compliance = s.inverse_compliance;
  k.dt_g_t_over_m2 = s.dt_g_t_over_m2;
  k.dt_over_m = s.dt_over_m;
  k.m_over_dt = s.m_over_dt;
  k.dt_mu_s_over_m = s.dt_mu_s_over_m;
  k.mover_mass_inv = c.mover_mass_inv_per_kg;
  k.mover_damping = c.mover_damping_n_s_m;
  k.guide_coefficient = c.guide.coefficient;
  k.guide_weight = c.guide.weight_n;
  k.guide_inverse_width = c.guide.inverse_sign_width_s_m;
  k.dt = dt_;
  const double position_limit = model.parameters().numerics.divergence_limit_um * 1e-6;
  const double speed_limit = model.parameters().numerics.divergence_speed_limit_m_s;
  k.position_limit_sq = position_limit * position_limit;
  k.speed_limit_sq = speed_limit * speed_limit;
  k.rest_q1 = model.constants().static_q1_m;
  k.jenkins = c.tangential == TangentialContact::jenkins;
  k.coulomb_guide = c.guide_model == GuideFrictionModel::implicit_coulomb;
  k.per_lane = c.effects.slow();
  for (std::size_t lane = 0; lane < padded_; ++lane) set_idle(lane);
}

BatchSimulator::~BatchSimulator() = default;

void BatchSimulator::set_lane(std::size_t lane, const MotorState& state, const DriveInput& drive) {
  const std::size_t p = padded_;
  double* x = a_->data.get();
  const DriveWaveform w = make_drive_waveform(drive, model_.coefficients().drive_amplitude_per_volt, dt_);
  double s = state.drive_sin;
  double c = state.drive_cos;
  const double r = std::hypot(s, c);
  if (r > 0.0 && std::isfinite(r)) {
    s /= r;
    c /= r;
  } else {
    s = 0.0;
    c = 1.0;
  }
  x[kQ1 * p + lane] = state.q1_m;
  x[kQ2 * p + lane] = state.q2_m;
  x[kXm * p + lane] = state.mover_position_m;
  x[kV1 * p + lane] = state.q1_dot_m_s;
  x[kV2 * p + lane] = state.q2_dot_m_s;
  x[kVm * p + lane] = state.mover_velocity_m_s;
  x[kDelta * p + lane] = a_->k.jenkins ? state.contact_deflection_m : 0.0;
  x[kSin * p + lane] = s;
  x[kCos * p + lane] = c;
  x[kTime * p + lane] = state.time_s;
  x[kAmplitude * p + lane] = w.amplitude_v;
  x[kCosPhase * p + lane] = w.cos_phase;
  x[kSinPhase * p + lane] = w.sin_phase;
  x[kRotationCos * p + lane] = w.rotation_cos;
  x[kRotationSin * p + lane] = w.rotation_sin;
  x[kLoad * p + lane] = drive.load_n;
  x[kNormal * p + lane] = 0.0;
  x[kFriction * p + lane] = 0.0;
  x[kGuide * p + lane] = 0.0;
  x[kDivergedFlag * p + lane] = 0.0;
  x[kDivergedCount * p + lane] = 0.0;
  // The slow states, held fixed (MotorSimulator::set_slow_states(..., frozen = true)): the
  // constants they change come from the scalar system itself.
  const MotorCoefficients& base = model_.coefficients();
  const EffectCoefficients& e = base.effects;
  const double temperature = e.thermal ? state.stator_temperature_rise_k : 0.0;
  const double distance = e.wear ? state.sliding_distance_m : 0.0;
  MotorSplitSystem system(base, dt_);
  if (e.thermal) {
    const ThermalFactors factors = thermal_factors(e, temperature);
    system.set_modal_factors(base, factors.stiffness, factors.damping);
  }
  if (e.wear) system.set_friction_coefficient(base.friction_coefficient * wear_friction_factor(e, distance));
  const MotorCoefficients& lane_k = system.coefficients();
  const MotorSplitSystem::StepConstants step = system.step_constants();
  x[kLaneK1 * p + lane] = lane_k.stator.l1.k;
  x[kLaneK2 * p + lane] = lane_k.stator.b2.k;
  x[kLaneC1 * p + lane] = lane_k.c1_n_s_m;
  x[kLaneC2 * p + lane] = lane_k.c2_n_s_m;
  x[kLaneA1 * p + lane] = step.a1_per_kg;
  x[kLaneA2 * p + lane] = step.a2_per_kg;
  x[kLaneInverseCompliance * p + lane] = step.inverse_compliance;
  x[kLaneDtGtOverM2 * p + lane] = step.dt_g_t_over_m2;
  x[kLaneFriction * p + lane] = lane_k.friction_coefficient;
  x[kLaneSlider * p + lane] = lane_k.slider_limit_per_normal_force_m_n;
  x[kLaneTemperature * p + lane] = temperature;
  x[kLaneDistance * p + lane] = distance;
  x[kLaneCommandedAmplitude * p + lane] = w.amplitude_v;
  x[kLaneDroopGain * p + lane] = 1.0;  // a fresh MotorSimulator's
  x[kLaneAngularFrequency * p + lane] = w.angular_frequency_rad_s;
  x[kLaneMidpointScale * p + lane] = 0.5 / std::cos(0.5 * w.angular_frequency_rad_s * dt_);
  set_lane_sampling(lane, false);
  reset_window(lane);
  a_->lane_idle[lane] = 0U;
  a_->group_active[lane / kLanePadding] = 1U;
}

void BatchSimulator::set_idle(std::size_t lane) {
  DriveInput none;
  none.amplitude_v = 0.0;
  set_lane(lane, model_.rest_state(), none);
  a_->lane_idle[lane] = 1U;
  const std::size_t first = lane / kLanePadding * kLanePadding;
  bool any = false;
  for (std::size_t l = first; l < first + kLanePadding; ++l) any = any || a_->lane_idle[l] == 0U;
  a_->group_active[lane / kLanePadding] = any ? 1U : 0U;
}

bool BatchSimulator::idle(std::size_t lane) const { return a_->lane_idle[lane] != 0U; }

void BatchSimulator::advance(std::uint64_t steps) {
  if (!model_.coefficients().effects.droop) {
    HWY_DYNAMIC_DISPATCH(AdvanceBatch)
    (a_->k, a_->data.get(), padded_, a_->group_active.data(), a_->group_sampling.data(), steps, clock_steps_);
    clock_steps_ += steps;
    return;
  }
  // Amplifier droop: the gain follows the motional current once per 64-step housekeeping block
  // (MotorSimulator::update_effects), per lane, between the vector blocks.
  while (steps > 0) {
    const std::uint64_t block = std::min<std::uint64_t>(steps, 64U - (clock_steps_ & 63U));
    HWY_DYNAMIC_DISPATCH(AdvanceBatch)
    (a_->k, a_->data.get(), padded_, a_->group_active.data(), a_->group_sampling.data(), block, clock_steps_);
    clock_steps_ += block;
    steps -= block;
    if ((clock_steps_ & 63U) == 0U) update_droop();
  }
}

void BatchSimulator::update_droop() {
  const std::size_t p = padded_;
  double* x = a_->data.get();
  const EffectCoefficients& e = model_.coefficients().effects;
  const double static_q1 = model_.constants().static_q1_m;
  for (std::size_t lane = 0; lane < lanes_; ++lane) {
    if (a_->lane_idle[lane] != 0U) continue;
    const double w = x[kLaneAngularFrequency * p + lane];
    const double inv_w = w > 0.0 ? 1.0 / w : 0.0;
    const Analytic z1{x[kQ1 * p + lane] - static_q1, -x[kV1 * p + lane] * inv_w};
    const Analytic z2{x[kQ2 * p + lane], -x[kV2 * p + lane] * inv_w};
    const double commanded = x[kLaneCommandedAmplitude * p + lane];
    const double target = droop_gain(e, w, x[kSin * p + lane], x[kCos * p + lane], x[kCosPhase * p + lane],
                                     x[kSinPhase * p + lane], commanded, z1, z2);
    double& gain = x[kLaneDroopGain * p + lane];
    gain += 0.5 * (target - gain);
    x[kAmplitude * p + lane] = commanded * gain;
  }
}

MotorState BatchSimulator::lane_state(std::size_t lane) const {
  const std::size_t p = padded_;
  const double* x = a_->data.get();
  MotorState s;
  s.q1_m = x[kQ1 * p + lane];
  s.q2_m = x[kQ2 * p + lane];
  s.mover_position_m = x[kXm * p + lane];
  s.q1_dot_m_s = x[kV1 * p + lane];
  s.q2_dot_m_s = x[kV2 * p + lane];
  s.mover_velocity_m_s = x[kVm * p + lane];
  s.contact_deflection_m = x[kDelta * p + lane];
  s.drive_sin = x[kSin * p + lane];
  s.drive_cos = x[kCos * p + lane];
  s.time_s = x[kTime * p + lane];
  s.stator_temperature_rise_k = x[kLaneTemperature * p + lane];
  s.sliding_distance_m = x[kLaneDistance * p + lane];
  return s;
}

InterfaceForces BatchSimulator::lane_forces(std::size_t lane) const {
  const std::size_t p = padded_;
  const double* x = a_->data.get();
  return {x[kNormal * p + lane], x[kFriction * p + lane], x[kGuide * p + lane]};
}

bool BatchSimulator::lane_diverged(std::size_t lane) const { return a_->data[kDivergedFlag * padded_ + lane] != 0.0; }

std::uint64_t BatchSimulator::lane_divergence_count(std::size_t lane) const {
  return static_cast<std::uint64_t>(a_->data[kDivergedCount * padded_ + lane]);
}

void BatchSimulator::reset_window(std::size_t lane) {
  const std::size_t p = padded_;
  double* x = a_->data.get();
  x[kUMin * p + lane] = kInfinity;
  x[kUMax * p + lane] = -kInfinity;
  x[kWMin * p + lane] = kInfinity;
  x[kWMax * p + lane] = -kInfinity;
  for (std::size_t f : {kContact, kFrictionSum, kFrictionSqSum, kNormalSum, kPowerSum, kSlipSum, kMoverSum}) {
    x[f * p + lane] = 0.0;
  }
  for (std::size_t f = kElecSamples; f <= kElecVBSq; ++f) x[f * p + lane] = 0.0;
}

void BatchSimulator::set_lane_sampling(std::size_t lane, bool on) {
  a_->lane_sampling[lane] = on ? 1U : 0U;
  const std::size_t first = lane / kLanePadding * kLanePadding;
  bool any = false;
  for (std::size_t l = first; l < first + kLanePadding; ++l) any = any || a_->lane_sampling[l] != 0U;
  a_->group_sampling[lane / kLanePadding] = any ? 1U : 0U;
}

ElectricalSums BatchSimulator::lane_electrical(std::size_t lane) const {
  const std::size_t p = padded_;
  const double* x = a_->data.get();
  auto at = [&](std::size_t field) { return x[field * p + lane]; };
  ElectricalSums e;
  e.samples = at(kElecSamples);
  e.duration_s = e.samples * static_cast<double>(MotorSimulator::kElectricalStride) * dt_;
  e.ss = at(kElecSS);
  e.cc = at(kElecCC);
  e.sc = at(kElecSC);
  e.a_s = at(kElecAS);
  e.a_c = at(kElecAC);
  e.b_s = at(kElecBS);
  e.b_c = at(kElecBC);
  e.ma_s = at(kElecMAS);
  e.ma_c = at(kElecMAC);
  e.mb_s = at(kElecMBS);
  e.mb_c = at(kElecMBC);
  e.power_a = at(kElecPowerA);
  e.power_b = at(kElecPowerB);
  e.a_sq = at(kElecASq);
  e.b_sq = at(kElecBSq);
  e.a_peak = at(kElecAPeak);
  e.b_peak = at(kElecBPeak);
  e.va_s = at(kElecVAS);
  e.va_c = at(kElecVAC);
  e.vb_s = at(kElecVBS);
  e.vb_c = at(kElecVBC);
  e.va_sq = at(kElecVASq);
  e.vb_sq = at(kElecVBSq);
  return e;
}

WindowStatistics BatchSimulator::window(std::size_t lane) const {
  const std::size_t p = padded_;
  const double* x = a_->data.get();
  WindowStatistics w;
  w.u_min_m = x[kUMin * p + lane];
  w.u_max_m = x[kUMax * p + lane];
  w.w_min_m = x[kWMin * p + lane];
  w.w_max_m = x[kWMax * p + lane];
  w.contact_s = x[kContact * p + lane];
  w.ft_sum_n_s = x[kFrictionSum * p + lane];
  w.ft2_sum_n2_s = x[kFrictionSqSum * p + lane];
  w.fn_sum_n_s = x[kNormalSum * p + lane];
  w.energy_j = x[kPowerSum * p + lane];
  w.slip_energy_j = x[kSlipSum * p + lane];
  w.mover_energy_j = x[kMoverSum * p + lane];
  return w;
}

}  // namespace swum
#endif  // HWY_ONCE
