// The groups of base parameters the discovery step may change (parameter_groups.h).
#include "analysis/discrepancy/parameter_groups.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "../discrepancy_test_support.h"

namespace swum {
namespace {

TEST(ParameterGroups, AFactorChangesEveryKeyOfTheGroupTogether) {
  const MotorParameters base = test::calibrated_motor();
  const FreeParameter f = group_free_parameter(*find_parameter_group("stator_damping"), base);
  EXPECT_EQ(f.origin, 1.0);
  MotorParameters p = base;
  f.apply(p, 1.4);
  EXPECT_DOUBLE_EQ(p.stator.damping_l1_n_s_m, 1.4 * base.stator.damping_l1_n_s_m);
  EXPECT_DOUBLE_EQ(p.stator.damping_b2_n_s_m, 1.4 * base.stator.damping_b2_n_s_m);
  // Applied twice from the same baseline: the value is absolute, not compounded.
  f.apply(p, 1.4);
  EXPECT_DOUBLE_EQ(p.stator.damping_l1_n_s_m, 1.4 * base.stator.damping_l1_n_s_m);
}

TEST(ParameterGroups, AShiftMovesBothNaturalFrequenciesByTheSameHertz) {
  const MotorParameters base = test::calibrated_motor();
  const FreeParameter f = group_free_parameter(*find_parameter_group("modal_frequencies"), base);
  EXPECT_EQ(f.origin, 0.0);
  EXPECT_EQ(f.unit, "Hz");
  MotorParameters p = base;
  f.apply(p, -150.0);
  EXPECT_DOUBLE_EQ(p.stator.target_l1_frequency_hz, base.stator.target_l1_frequency_hz - 150.0);
  EXPECT_DOUBLE_EQ(p.stator.target_b2_frequency_hz, base.stator.target_b2_frequency_hz - 150.0);
}

TEST(ParameterGroups, ANegativeConstantKeepsItsSignAndBoundsStayInTheDocumentedRanges) {
  const MotorParameters base = test::calibrated_motor();
  ASSERT_LT(base.stator.c1111_pa, 0.0);
  const FreeParameter f = group_free_parameter(*find_parameter_group("elastic_nonlinearity"), base);
  MotorParameters p = base;
  f.apply(p, 0.5);
  EXPECT_DOUBLE_EQ(p.stator.c1111_pa, 0.5 * base.stator.c1111_pa);
  EXPECT_GT(f.lower, 0.0);
  for (const ParameterGroup& g : parameter_groups()) {
    const FreeParameter free = group_free_parameter(g, base);
    ASSERT_LT(free.lower, free.origin) << g.name;
    ASSERT_GT(free.upper, free.origin) << g.name;
    MotorParameters lo = base, hi = base;
    free.apply(lo, free.lower);
    free.apply(hi, free.upper);
    EXPECT_NO_THROW(validate_parameters(lo, g.name)) << g.name;
    EXPECT_NO_THROW(validate_parameters(hi, g.name)) << g.name;
  }
}

TEST(ParameterGroups, GroupsThatDoNotApplyAreRefusedSayingWhy) {
  MotorParameters explicit_geometry = test::calibrated_motor();
  explicit_geometry.stator.geometry = GeometryMode::explicit_size;
  const ParameterGroup& modal = *find_parameter_group("modal_frequencies");
  EXPECT_TRUE(group_parameters(modal, explicit_geometry).empty());
  try {
    (void)group_free_parameter(modal, explicit_geometry);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("from_frequencies"), std::string::npos) << e.what();
  }
  MotorParameters rigid = test::calibrated_motor();
  rigid.contact.tangential_stiffness_n_m = 0.0;  // a rigid contact: no tip compliance to change
  EXPECT_TRUE(group_parameters(*find_parameter_group("tip_compliance"), rigid).empty());
  EXPECT_NE(group_not_applicable_reason(*find_parameter_group("tip_compliance"), rigid).find("are 0"),
            std::string::npos);
  EXPECT_EQ(find_parameter_group("no_such_group"), nullptr);
  EXPECT_NE(parameter_group_names().find("stator_damping"), std::string::npos);
}

TEST(ParameterGroups, NoGroupIsAlreadyALibraryEffect) {
  // What the library changes (effects.*) is never a base group: a group and an effect must not be
  // the same change under two names.
  for (const ParameterGroup& g : parameter_groups()) {
    for (std::string_view key : g.keys) EXPECT_FALSE(key.starts_with("effects.")) << g.name;
  }
}

}  // namespace
}  // namespace swum
