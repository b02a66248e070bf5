#include "core/units.hpp"

#include <gtest/gtest.h>

namespace beadtwin {
namespace {

TEST(Units, ParsesLengthsInAnyUnit) {
  EXPECT_DOUBLE_EQ(parse_quantity("0.83 in", Dimension::kLength), 0.83 * 25.4);
  EXPECT_DOUBLE_EQ(parse_quantity("5 mm", Dimension::kLength), 5.0);
  EXPECT_DOUBLE_EQ(parse_quantity("1.5m", Dimension::kLength), 1500.0);
  EXPECT_DOUBLE_EQ(parse_quantity("  2 ft ", Dimension::kLength), 609.6);
}

TEST(Units, BareNumberTakesTheDefaultUnit) {
  EXPECT_DOUBLE_EQ(parse_quantity("2", Dimension::kLength, "in"), 50.8);
  EXPECT_DOUBLE_EQ(parse_quantity("2", Dimension::kLength), 2.0);  // internal unit
}

TEST(Units, Temperatures) {
  EXPECT_DOUBLE_EQ(parse_quantity("240 C", Dimension::kTemperature), 240.0);
  EXPECT_NEAR(parse_quantity("373.15 K", Dimension::kTemperature), 100.0, 1e-12);
  EXPECT_NEAR(parse_quantity("212 F", Dimension::kTemperature), 100.0, 1e-12);
  EXPECT_NEAR(from_internal(100.0, "F", Dimension::kTemperature), 212.0, 1e-12);
}

TEST(Units, FlowsSpeedsAnglesFractions) {
  // 150 lb/h = 150 * 0.45359237 kg / 3600 s
  EXPECT_NEAR(parse_quantity("150 lb/h", Dimension::kMassFlow), 150 * 0.45359237 / 3600, 1e-15);
  EXPECT_DOUBLE_EQ(parse_quantity("6 in/s", Dimension::kSpeed), 152.4);
  EXPECT_DOUBLE_EQ(parse_quantity("600 mm/min", Dimension::kSpeed), 10.0);
  EXPECT_DOUBLE_EQ(parse_quantity("45 deg", Dimension::kAngle), 45.0);
  EXPECT_NEAR(parse_quantity("1 rad", Dimension::kAngle), 57.29577951308232, 1e-12);
  EXPECT_DOUBLE_EQ(parse_quantity("10 %", Dimension::kFraction), 0.1);
  EXPECT_DOUBLE_EQ(parse_quantity("0.25", Dimension::kFraction), 0.25);
  EXPECT_DOUBLE_EQ(parse_quantity("1 cm3/s", Dimension::kVolumeFlow), 1000.0);
  EXPECT_DOUBLE_EQ(parse_quantity("1 mm³/s", Dimension::kVolumeFlow), 1.0);
  EXPECT_DOUBLE_EQ(parse_quantity("150 kJ/mol", Dimension::kMolarEnergy), 150e3);
}

TEST(Units, BadUnitNamesWhatWasExpected) {
  try {
    (void)parse_quantity("5 furlongs", Dimension::kLength);
    FAIL() << "no error for an unknown unit";
  } catch (const QuantityError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("furlongs"), std::string::npos) << msg;
    EXPECT_NE(msg.find("length"), std::string::npos) << msg;
    EXPECT_NE(msg.find("mm"), std::string::npos) << msg;
  }
  // A temperature is not a length.
  EXPECT_THROW((void)parse_quantity("240 C", Dimension::kLength), QuantityError);
  EXPECT_THROW((void)parse_quantity("abc", Dimension::kLength), QuantityError);
  EXPECT_THROW((void)parse_quantity("", Dimension::kLength), QuantityError);
  EXPECT_THROW((void)parse_quantity("inf mm", Dimension::kLength), QuantityError);
  EXPECT_THROW((void)parse_quantity("3 mm", Dimension::kDimensionless), QuantityError);
}

}  // namespace
}  // namespace beadtwin
