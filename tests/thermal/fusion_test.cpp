// Tests of the fusion window shared by the thermal models (thermal/fusion.hpp): the reptation time and the
// verdicts' names.
#include "thermal/fusion.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace beadtwin::thermal {
namespace {

TEST(FusionTest, ReptationTimeFollowsArrhenius) {
  const Material m;  // t_ref 1 s at 200 °C, E_a 150 kJ/mol, no healing below 110 °C
  EXPECT_DOUBLE_EQ(reptation_time_s(m, m.healing_ref_temp_c), m.reptation_time_ref_s);
  // By hand: 150000 / 8.314462618 · (1/423.15 − 1/473.15) = 4.5054055; exp(4.5054055) = 90.50504 s.
  EXPECT_NEAR(reptation_time_s(m, 150.0), 90.50504, 1e-4);
  // At the threshold itself: 150000 / 8.314462618 · (1/383.15 − 1/473.15) = 8.9563676 → 7757.129 s.
  EXPECT_NEAR(reptation_time_s(m, 110.0), 7757.129, 1e-2);
  EXPECT_TRUE(std::isinf(reptation_time_s(m, 109.9)));
  Material shifted = m;
  shifted.reptation_time_ref_s = 3.0;
  EXPECT_NEAR(reptation_time_s(shifted, 150.0), 3.0 * 90.50504, 3e-4);
}

TEST(FusionTest, VerdictNames) {
  EXPECT_EQ(to_string(Verdict::kOk), "ok");
  EXPECT_EQ(to_string(Verdict::kTooHot), "too_hot");
  EXPECT_EQ(to_string(Verdict::kTooCold), "too_cold");
  EXPECT_EQ(to_string(Verdict::kNoInterface), "no_interface");
}

}  // namespace
}  // namespace beadtwin::thermal
