// Tests of the fusion window shared by the thermal models (thermal/fusion.hpp): the reptation time by the
// WLF law and the Arrhenius law against hand-computed values, the switch between them, the rate's
// derivative, the inverse the layer-time window uses, and the verdicts' names.
#include "thermal/fusion.hpp"

#include <cmath>
#include <initializer_list>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace beadtwin::thermal {
namespace {

// The default material: T_g 110 °C, t_ref 1 s at 200 °C, WLF with C1 = 17.44, C2 = 51.6 K up to T_g + 100 K
// (210 °C), E_a 150 kJ/mol above it, no healing below 110 °C.
Material arrhenius() {
  Material m;
  m.healing_law = HealingLaw::kArrhenius;
  return m;
}

TEST(FusionTest, ReptationTimeFollowsArrheniusWhereTheMaterialSaysSo) {
  const Material m = arrhenius();
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

TEST(FusionTest, ReptationTimeFollowsWlfFromTheGlassTransition) {
  const Material m;
  ASSERT_EQ(m.healing_law, HealingLaw::kWlf);
  EXPECT_DOUBLE_EQ(reptation_time_s(m, 200.0), 1.0);
  // log10 t_w(T)/t_w(200 °C) = −17.44 (T − 110)/(51.6 + T − 110) + 17.44 · 90/141.6, by hand:
  // 17.44 · 90/141.6 = 11.0847458 and 17.44 · 40/91.6 = 7.6157205, so at 150 °C 3.4690253 decades.
  EXPECT_NEAR(std::log10(reptation_time_s(m, 150.0)), 3.4690253, 1e-7);
  // 160 °C: 17.44 · 50/101.6 = 8.5826772, 2.5020686 decades; 140 °C: 17.44 · 30/81.6 = 6.4117647,
  // 4.6729811 decades; 120 °C: 17.44 · 10/61.6 = 2.8311688, 8.2535770 decades; at T_g itself 11.0847458.
  EXPECT_NEAR(std::log10(reptation_time_s(m, 160.0)), 2.5020686, 1e-7);
  EXPECT_NEAR(std::log10(reptation_time_s(m, 140.0)), 4.6729811, 1e-7);
  EXPECT_NEAR(std::log10(reptation_time_s(m, 120.0)), 8.2535770, 1e-7);
  EXPECT_NEAR(std::log10(reptation_time_s(m, 110.0)), 11.0847458, 1e-7);
  // 190 °C: 17.44 · 80/131.6 = 10.6018237, 0.4829221 decades; hotter than the reference, 205 °C:
  // 17.44 · 95/146.6 = 11.3015007, −0.2167549 decades.
  EXPECT_NEAR(std::log10(reptation_time_s(m, 190.0)), 0.4829221, 1e-7);
  EXPECT_NEAR(std::log10(reptation_time_s(m, 205.0)), -0.2167549, 1e-7);
  EXPECT_TRUE(std::isinf(reptation_time_s(m, 109.9)));  // the healing threshold still applies
  // The Arrhenius law from the same reference heals 9.4 times faster at 160 °C, 185 times at 140 °C and
  // 77,000 times at 120 °C.
  EXPECT_NEAR(reptation_time_s(m, 160.0) / reptation_time_s(arrhenius(), 160.0), 9.4, 0.1);
  EXPECT_NEAR(reptation_time_s(m, 140.0) / reptation_time_s(arrhenius(), 140.0), 185.4, 0.1);
  EXPECT_NEAR(reptation_time_s(m, 120.0) / reptation_time_s(arrhenius(), 120.0), 76561.0, 1.0);
  // Other constants: C1 = 10, C2 = 60 K at 150 °C: −10 · 40/100 + 10 · 90/150 = 2 decades.
  Material other = m;
  other.wlf_c1 = 10.0;
  other.wlf_c2_k = 60.0;
  EXPECT_NEAR(reptation_time_s(other, 150.0), 100.0, 1e-9);
}

TEST(FusionTest, AboveTheWlfRangeArrheniusTakesOverContinuously) {
  const Material m;  // the switch at T_g + 100 K = 210 °C
  const double at_switch = reptation_time_s(m, 210.0);
  // WLF there: −17.44 · 100/151.6 + 11.0847458 = −0.4192120 decades.
  EXPECT_NEAR(std::log10(at_switch), -0.4192120, 1e-7);
  EXPECT_NEAR(reptation_time_s(m, 210.0 + 1e-9), at_switch, 1e-9 * at_switch);
  EXPECT_NEAR(reptation_time_s(m, 210.0 - 1e-9), at_switch, 1e-9 * at_switch);
  // Above it, the material's activation energy: t_w(230)/t_w(210) = exp(150000 / 8.314462618 · (1/503.15 −
  // 1/483.15)) = exp(−1.4842519) = 0.2266719.
  EXPECT_NEAR(reptation_time_s(m, 230.0) / at_switch, 0.2266719, 1e-7);
  // A reference above the switch: the WLF part is reached through the Arrhenius one, the same curve scaled.
  Material hot_ref = m;
  hot_ref.healing_ref_temp_c = 230.0;
  hot_ref.reptation_time_ref_s = reptation_time_s(m, 230.0);
  for (const double t : {150.0, 200.0, 215.0})
    EXPECT_NEAR(reptation_time_s(hot_ref, t), reptation_time_s(m, t), 1e-9 * reptation_time_s(m, t)) << t;
  // No WLF range: Arrhenius from T_g up, the same as the Arrhenius law scaled to meet WLF at T_g.
  Material none = m;
  none.wlf_range_k = 0.0;
  none.healing_ref_temp_c = 110.0;
  Material plain = arrhenius();
  plain.healing_ref_temp_c = 110.0;
  EXPECT_NEAR(reptation_time_s(none, 170.0), reptation_time_s(plain, 170.0), 1e-12);
}

TEST(FusionTest, RateDerivativeMatchesFiniteDifferencesOnEachSide) {
  for (const Material& m : {Material{}, arrhenius()}) {
    const Reptation r(m);
    for (const double t : {112.0, 150.0, 205.0, 209.0, 211.0, 240.0}) {
      const double h = 1e-4;
      const double numeric = (r.rate_per_s(t + h) - r.rate_per_s(t - h)) / (2.0 * h);
      EXPECT_NEAR(r.rate_derivative(t), numeric, 1e-6 * std::abs(numeric)) << t;
    }
    EXPECT_EQ(r.rate_derivative(100.0), 0.0);  // below the threshold
  }
  // At the switch the slope of ln(rate) jumps from WLF's 17.44 ln10 · 51.6/151.6² = 0.0901599 /K to
  // Arrhenius's 150000 / 8.314462618 / 483.15² = 0.0772846 /K: the derivative is the Arrhenius side's.
  const Reptation r{Material{}};
  EXPECT_NEAR(r.rate_derivative(210.0) / r.rate_per_s(210.0), 0.0772846, 1e-7);
  EXPECT_NEAR(r.rate_derivative(209.999999) / r.rate_per_s(209.999999), 0.0901599, 1e-6);
}

TEST(FusionTest, TemperatureAtALogTimeInvertsIt) {
  for (const Material& m : {Material{}, arrhenius()}) {
    const Reptation r(m);
    for (const double t : {105.0, 130.0, 180.0, 209.0, 215.0, 300.0})
      EXPECT_NEAR(r.temp_at_log_time(r.log_time(t)), t, 1e-9) << t;
  }
  const Reptation wlf{Material{}};
  // Shorter than any temperature gives (the Arrhenius part tends to a finite time as T grows): none.
  EXPECT_TRUE(std::isinf(wlf.temp_at_log_time(-100.0)));
  // The WLF shift diverges at T_g − C2 = 58.4 °C.
  EXPECT_TRUE(std::isinf(wlf.log_time(58.0)));
  EXPECT_NEAR(wlf.temp_at_log_time(1e300), 110.0 - 51.6, 1e-6);
}

TEST(FusionTest, AReferenceWhereTheWlfShiftDivergesIsAnInputError) {
  Material m;
  m.healing_ref_temp_c = 50.0;  // below T_g − C2
  try {
    const Reptation r(m);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "fusion.healing_ref_temp");
  }
}

TEST(FusionTest, VerdictNames) {
  EXPECT_EQ(to_string(Verdict::kOk), "ok");
  EXPECT_EQ(to_string(Verdict::kTooHot), "too_hot");
  EXPECT_EQ(to_string(Verdict::kTooCold), "too_cold");
  EXPECT_EQ(to_string(Verdict::kNoInterface), "no_interface");
}

}  // namespace
}  // namespace beadtwin::thermal
