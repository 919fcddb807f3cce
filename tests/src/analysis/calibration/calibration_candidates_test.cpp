// The base parameters `swum calibrate` may fit: every candidate is a real parameter of the
// table, applies only where the prior makes it a parameter, and becomes a free parameter around
// the prior value, bounded on the prior's side of zero and inside the documented range.
#include "analysis/calibration/calibration_candidates.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "../discrepancy_test_support.h"
#include "formats/parameter_file.h"

namespace swum {
namespace {

MotorParameters li2019() { return test::calibrated_motor(); }

const ParameterSpec& spec_of(std::string_view name) {
  const std::size_t dot = name.find('.');
  const ParameterSpec* spec = find_parameter_spec(name.substr(0, dot), name.substr(dot + 1));
  if (spec == nullptr) throw std::logic_error("no parameter " + std::string(name));
  return *spec;
}

bool contains(const std::vector<const CalibrationCandidate*>& candidates, std::string_view name) {
  for (const CalibrationCandidate* c : candidates) {
    if (c->name == name) return true;
  }
  return false;
}

// The message of calibration_free_parameter(name, prior), or "" when it applies.
std::string error_of(std::string_view name, const MotorParameters& prior) {
  const CalibrationCandidate* c = find_calibration_candidate(name);
  if (c == nullptr) return "no candidate " + std::string(name);
  try {
    (void)calibration_free_parameter(*c, prior);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(CalibrationCandidates, EveryCandidateIsARealParameterOnceWithASpread) {
  const auto candidates = calibration_candidates();
  ASSERT_GE(candidates.size(), 10u);
  std::set<std::string_view> names;
  std::string listed;
  for (const CalibrationCandidate& c : candidates) {
    const std::size_t dot = c.name.find('.');
    ASSERT_NE(dot, std::string_view::npos) << c.name;
    const ParameterSpec* spec = find_parameter_spec(c.name.substr(0, dot), c.name.substr(dot + 1));
    ASSERT_NE(spec, nullptr) << c.name;
    EXPECT_EQ(spec->name(), c.name);
    EXPECT_EQ(spec->kind, ParameterKind::real) << c.name;
    EXPECT_TRUE(names.insert(c.name).second) << "duplicate " << c.name;
    EXPECT_FALSE(c.why.empty()) << c.name;
    EXPECT_TRUE(c.relative_spread > 0.0 || c.absolute_spread > 0.0) << c.name;
    EXPECT_GT(c.bound_spreads, 0.0) << c.name;
    EXPECT_GT(c.min_fraction, 0.0) << c.name;
    EXPECT_LT(c.min_fraction, 1.0) << c.name;
    EXPECT_EQ(find_calibration_candidate(c.name), &c) << c.name;
    listed += (listed.empty() ? "" : ", ") + std::string(c.name);
  }
  EXPECT_EQ(calibration_candidate_names(), listed);
  EXPECT_EQ(calibration_candidate_names().rfind("contact.preload_n, stator.damping_l1_n_s_m, ", 0), 0u);
  EXPECT_EQ(find_calibration_candidate("contact.preload"), nullptr);
  EXPECT_EQ(find_calibration_candidate("stator.length_mm"), nullptr);  // geometry: not fitted
  EXPECT_EQ(find_calibration_candidate("numerics.time_step_ns"), nullptr);
}

TEST(CalibrationCandidates, AllApplyToLi2019InTableOrder) {
  const MotorParameters prior = li2019();
  const auto applicable = applicable_candidates(prior);
  const auto all = calibration_candidates();
  ASSERT_EQ(applicable.size(), all.size());
  for (std::size_t k = 0; k < all.size(); ++k) EXPECT_EQ(applicable[k], &all[k]) << all[k].name;
  EXPECT_TRUE(contains(applicable, "stator.target_l1_frequency_hz"));
  EXPECT_TRUE(contains(applicable, "stator.target_b2_frequency_hz"));
  EXPECT_TRUE(contains(applicable, "contact.tangential_stiffness_n_m"));
}

TEST(CalibrationCandidates, TargetFrequenciesOnlyWithGeometryFromFrequencies) {
  MotorParameters prior = li2019();
  prior.stator.geometry = GeometryMode::explicit_size;
  const auto applicable = applicable_candidates(prior);
  EXPECT_EQ(applicable.size(), calibration_candidates().size() - 2);
  EXPECT_FALSE(contains(applicable, "stator.target_l1_frequency_hz"));
  EXPECT_FALSE(contains(applicable, "stator.target_b2_frequency_hz"));
  EXPECT_TRUE(contains(applicable, "contact.tangential_stiffness_n_m"));
  EXPECT_TRUE(contains(applicable, "stator.substrate_thickness_mm"));
  const std::string message = error_of("stator.target_l1_frequency_hz", prior);
  EXPECT_NE(message.find("stator.target_l1_frequency_hz cannot be fitted"), std::string::npos) << message;
  EXPECT_NE(message.find("explicit"), std::string::npos) << message;
  EXPECT_NE(error_of("stator.target_b2_frequency_hz", prior).find("explicit"), std::string::npos);
  EXPECT_EQ(error_of("stator.damping_l1_n_s_m", prior), "");
}

TEST(CalibrationCandidates, TangentialStiffnessOnlyForAJenkinsContact) {
  MotorParameters prior = li2019();
  prior.contact.tangential_stiffness_n_m = 0.0;
  const auto applicable = applicable_candidates(prior);
  EXPECT_EQ(applicable.size(), calibration_candidates().size() - 1);
  EXPECT_FALSE(contains(applicable, "contact.tangential_stiffness_n_m"));
  EXPECT_TRUE(contains(applicable, "stator.target_l1_frequency_hz"));
  const std::string message = error_of("contact.tangential_stiffness_n_m", prior);
  EXPECT_NE(message.find("contact.tangential_stiffness_n_m cannot be fitted"), std::string::npos) << message;
  EXPECT_NE(message.find("rigid"), std::string::npos) << message;
}

TEST(CalibrationCandidates, AZeroPriorWithoutAFallbackHasNoScale) {
  MotorParameters prior = li2019();
  prior.mover.damping_n_s_m = 0.0;
  EXPECT_FALSE(contains(applicable_candidates(prior), "mover.damping_n_s_m"));
  EXPECT_NE(error_of("mover.damping_n_s_m", prior).find("prior value is 0"), std::string::npos);

  // The non-linear constants have a fallback magnitude: at 0 they are fitted both ways.
  prior.stator.c1111_pa = 0.0;
  ASSERT_TRUE(contains(applicable_candidates(prior), "stator.c1111_pa"));
  const CalibrationCandidate& c = *find_calibration_candidate("stator.c1111_pa");
  const FreeParameter p = calibration_free_parameter(c, prior);
  EXPECT_EQ(p.origin, 0.0);
  EXPECT_DOUBLE_EQ(p.scale, c.relative_spread * c.fallback_magnitude);
  EXPECT_GT(p.scale, 0.0);
  EXPECT_DOUBLE_EQ(p.lower, -c.bound_spreads * p.scale);
  EXPECT_DOUBLE_EQ(p.upper, c.bound_spreads * p.scale);
}

TEST(CalibrationCandidates, FreeParametersAroundLi2019) {
  const MotorParameters prior = li2019();
  for (const CalibrationCandidate* c : applicable_candidates(prior)) {
    const ParameterSpec& spec = spec_of(c->name);
    const double value = spec.get(prior);
    const FreeParameter p = calibration_free_parameter(*c, prior);
    EXPECT_EQ(p.name, c->name);
    EXPECT_EQ(p.unit, spec.unit) << c->name;
    EXPECT_EQ(p.origin, value) << c->name;
    EXPECT_GT(p.scale, 0.0) << c->name;
    if (c->absolute_spread == 0.0) {
      EXPECT_DOUBLE_EQ(p.scale, c->relative_spread * std::abs(value)) << c->name;
    }
    EXPECT_LT(p.lower, p.origin) << c->name;
    EXPECT_GT(p.upper, p.origin) << c->name;
    EXPECT_GE(p.lower, spec.min_value) << c->name;
    EXPECT_LE(p.upper, spec.max_value) << c->name;
    // On the prior's side of zero, at least min_fraction x |prior| from it.
    if (value > 0.0) {
      EXPECT_GE(p.lower, c->min_fraction * value * (1 - 1e-12)) << c->name;
    } else {
      EXPECT_LE(p.upper, c->min_fraction * value * (1 - 1e-12)) << c->name;
    }
    // apply() writes the value through the table and nothing else.
    ASSERT_TRUE(p.apply) << c->name;
    MotorParameters moved = prior;
    const double target = 0.5 * (p.origin + p.upper);
    p.apply(moved, target);
    EXPECT_EQ(spec.get(moved), target) << c->name;
    EXPECT_EQ(spec.get(prior), value) << c->name;
  }
}

TEST(CalibrationCandidates, NegativeNonLinearConstantsStayNegative) {
  const MotorParameters prior = li2019();
  ASSERT_LT(prior.stator.c1111_pa, 0.0);
  const CalibrationCandidate& c = *find_calibration_candidate("stator.c1111_pa");
  const FreeParameter p = calibration_free_parameter(c, prior);
  EXPECT_EQ(p.origin, -0.85e17);
  EXPECT_DOUBLE_EQ(p.scale, 0.5 * 0.85e17);
  EXPECT_DOUBLE_EQ(p.lower, -0.85e17 - 3.0 * 0.5 * 0.85e17);  // 2.5 x the prior
  EXPECT_LT(p.upper, 0.0);
  EXPECT_DOUBLE_EQ(p.upper, 0.05 * -0.85e17);  // the side-of-zero limit, not prior + 3 spreads
  MotorParameters moved = prior;
  p.apply(moved, -1.2e17);
  EXPECT_EQ(moved.stator.c1111_pa, -1.2e17);

  ASSERT_LT(prior.stator.c111_pa, 0.0);
  const FreeParameter q = calibration_free_parameter(*find_calibration_candidate("stator.c111_pa"), prior);
  EXPECT_LT(q.upper, 0.0);
  EXPECT_LT(q.lower, q.origin);
}

TEST(CalibrationCandidates, PositiveConstantsStayPositive) {
  const MotorParameters prior = li2019();
  const FreeParameter e3111 = calibration_free_parameter(*find_calibration_candidate("stator.e3111_c_per_v_m"), prior);
  EXPECT_DOUBLE_EQ(e3111.lower, 0.05 * 6.4235e-3);
  EXPECT_DOUBLE_EQ(e3111.upper, 6.4235e-3 * 2.5);
  const FreeParameter preload = calibration_free_parameter(*find_calibration_candidate("contact.preload_n"), prior);
  EXPECT_EQ(preload.origin, 24.8);
  EXPECT_DOUBLE_EQ(preload.scale, 2.48);
  EXPECT_DOUBLE_EQ(preload.lower, 24.8 - 3 * 2.48);
  EXPECT_DOUBLE_EQ(preload.upper, 24.8 + 3 * 2.48);
  const FreeParameter kt = calibration_free_parameter(*find_calibration_candidate("contact.tangential_stiffness_n_m"),
                                                      prior);
  EXPECT_DOUBLE_EQ(kt.lower, 0.2e8);  // 2e8 - 3 x 0.3 x 2e8 = 0.1 x 2e8: still a Jenkins contact
  EXPECT_GT(kt.lower, 0.0);
}

TEST(CalibrationCandidates, TargetFrequenciesHaveAnAbsoluteSpreadOf100Hz) {
  const MotorParameters prior = li2019();
  const struct {
    const char* name;
    double value;
  } cases[] = {{"stator.target_l1_frequency_hz", 39516.0}, {"stator.target_b2_frequency_hz", 39469.0}};
  for (const auto& k : cases) {
    const CalibrationCandidate& c = *find_calibration_candidate(k.name);
    EXPECT_EQ(c.absolute_spread, 100.0) << k.name;
    const FreeParameter p = calibration_free_parameter(c, prior);
    EXPECT_EQ(p.origin, k.value) << k.name;
    EXPECT_EQ(p.scale, 100.0) << k.name;
    EXPECT_EQ(p.unit, "Hz") << k.name;
    EXPECT_DOUBLE_EQ(p.lower, k.value - c.bound_spreads * 100.0) << k.name;
    EXPECT_DOUBLE_EQ(p.upper, k.value + c.bound_spreads * 100.0) << k.name;
    MotorParameters moved = prior;
    p.apply(moved, k.value + 150.0);
    EXPECT_EQ(spec_of(k.name).get(moved), k.value + 150.0) << k.name;
  }
}

}  // namespace
}  // namespace swum
