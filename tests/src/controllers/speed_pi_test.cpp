// The amplitude PI of `swum control` (src/controllers/speed_pi.h): proportional plus integral of
// the error along the target's direction, clamped to [0, max], with conditional integration.
#include "controllers/speed_pi.h"

#include <gtest/gtest.h>

namespace swum {
namespace {

TEST(SpeedPi, ProportionalPlusIntegralOfTheErrorAlongTheTargetsDirection) {
  SpeedPi pi({0.5, 50.0, 500.0});
  // error 100 mm/s for 1 ms: P = 50 V, I = 50 * 100 * 0.001 = 5 V
  EXPECT_DOUBLE_EQ(pi.update(300.0, 200.0, 0.001), 55.0);
  EXPECT_DOUBLE_EQ(pi.integral_v(), 5.0);
  // Backwards: target -300, speed -200 is the same error magnitude.
  SpeedPi backwards({0.5, 50.0, 500.0});
  EXPECT_DOUBLE_EQ(backwards.update(-300.0, -200.0, 0.001), 55.0);
  // Moving the wrong way is a larger error, not a smaller one.
  SpeedPi wrong_way({0.5, 0.0, 500.0});
  EXPECT_DOUBLE_EQ(wrong_way.update(100.0, -20.0, 0.001), 60.0);
  EXPECT_DOUBLE_EQ(pi.update(0.0, 123.0, 0.001), 0.0);  // a zero target drives nothing
  EXPECT_DOUBLE_EQ(pi.integral_v(), 0.0);
}

TEST(SpeedPi, AntiWindupKeepsTheIntegralFromGrowingWhileSaturated) {
  SpeedPi pi({0.5, 50.0, 100.0});
  // A target the drive cannot reach: the output sits at the limit, the integral stops at it.
  for (int i = 0; i < 10000; ++i) EXPECT_LE(pi.update(1000.0, 0.0, 0.001), 100.0);
  EXPECT_LE(pi.integral_v(), 100.0);
  // Conditional integration: P alone saturates (error 1000 -> 500 V), the integral stays where it was.
  SpeedPi conditional({0.5, 50.0, 100.0});
  conditional.update(1000.0, 0.0, 0.001);
  EXPECT_DOUBLE_EQ(conditional.integral_v(), 0.0);
  // Leaving saturation is immediate once the error turns: no wound-up integral to unwind.
  EXPECT_LT(pi.update(1000.0, 1100.0, 0.001), 100.0);
  // The output does reach the limit when P alone does not (a phase open: 150 mm/s short of
  // 300): the integral stops exactly where P + I = max, not one step before it.
  SpeedPi short_of_limit({0.5, 50.0, 450.0});
  double out_amplitude_v = 0.0;
  for (int i = 0; i < 1000; ++i) out_amplitude_v = short_of_limit.update(300.0, 150.0, 0.001);
  EXPECT_DOUBLE_EQ(out_amplitude_v, 450.0);
  EXPECT_DOUBLE_EQ(short_of_limit.integral_v(), 450.0 - 0.5 * 150.0);
  // Never below 0 V.
  SpeedPi low({0.5, 50.0, 100.0});
  EXPECT_DOUBLE_EQ(low.update(10.0, 500.0, 0.001), 0.0);
  EXPECT_DOUBLE_EQ(low.integral_v(), 0.0);
}

TEST(SpeedPi, GainsOutsideTheirRangeAreRefusedAtConstructionNamingTheOption) {
  EXPECT_THROW(SpeedPi({-0.1, 50.0, 500.0}), std::invalid_argument);
  EXPECT_THROW(SpeedPi({0.5, -1.0, 500.0}), std::invalid_argument);
  try {
    SpeedPi({0.5, 50.0, 0.0});
    FAIL() << "max_amplitude_v 0 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--max-amplitude-v: must be > 0");
  }
}

}  // namespace
}  // namespace swum
