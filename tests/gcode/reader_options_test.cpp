#include "gcode/reader_options.hpp"

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "gcode/dialect.hpp"

namespace beadtwin::gcode {
namespace {

using Codes = std::vector<std::string>;

TEST(ReaderOptions, TheDefaultsValidate) {
  EXPECT_NO_THROW(validate(ReaderOptions{}));
  EXPECT_FALSE(default_ignored_codes().empty());
}

TEST(ReaderOptions, ValidateNamesEveryOptionAtFault) {
  ReaderOptions o;
  o.melt_on = {"23"};  // no letter
  o.chord_tolerance_mm = 0;
  o.default_feed_mm_s = -1;
  o.default_bead_width_mm = 5;
  o.default_layer_height_mm = 6;
  o.max_moves = 0;
  try {
    validate(o);
    ADD_FAILURE() << "bad options taken";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "reader");
    for (const char* named : {"reader.melt_on", "reader.chord_tolerance_mm", "reader.default_feed_mm_s",
                              "reader.default_layer_height_mm", "reader.max_moves"})
      EXPECT_NE(e.message().find(named), std::string::npos) << named << " in: " << e.message();
  }
  ReaderOptions constant_feed;
  Extruder drive;
  drive.kind = ExtruderKind::kFilament;
  drive.filament_diameter_mm = 1.75;
  drive.constant_feed_mm_s = 2;
  constant_feed.extruder = drive;
  constant_feed.melt_on.clear();
  EXPECT_THROW(validate(constant_feed), InputError) << "a constant feed needs a melt-on code";
}

// The speed word is one of the letters the reader gives no other meaning, or none; every other letter (and
// anything that is not one upper-case letter) is refused at reader.rpm_word.
TEST(ReaderOptions, TheSpeedWordIsALetterWithNoOtherMeaning) {
  ReaderOptions o;
  for (const std::string_view free : kSpeedWords) {
    o.rpm_word = free;
    EXPECT_NO_THROW(validate(o)) << free;
  }
  o.rpm_word.clear();
  EXPECT_NO_THROW(validate(o)) << "no speed word";
  std::vector<std::string> refused = {"s", "SS", "S1", " ", "#"};
  for (char c = 'A'; c <= 'Z'; ++c)
    if (std::find(kSpeedWords.begin(), kSpeedWords.end(), std::string(1, c)) == kSpeedWords.end())
      refused.emplace_back(1, c);
  EXPECT_EQ(refused.size(), 5u + 26u - kSpeedWords.size());
  for (const std::string& word : refused) {
    o.rpm_word = word;
    try {
      validate(o);
      ADD_FAILURE() << "speed word '" << word << "' taken";
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), "reader");
      EXPECT_NE(e.message().find("reader.rpm_word"), std::string::npos) << e.message();
    }
  }
}

TEST(ReaderOptions, ReaderOptionsForTakesTheDialectsCodesUnitsAndRapidFeed) {
  GcodeDialect d;
  d.melt_on = "M3";
  d.melt_off = "M5";
  d.roller_down = "M60";
  d.roller_up = "";
  d.prime_code = "M70";
  d.reverse_on = "M71";
  d.reverse_off = "M72";
  d.heat_on = "M80";
  d.heat_off = "M81";
  d.rpm_word = "Q";
  d.inches = true;
  d.rapid_feed_mm_s = 500;
  const ReaderOptions o = reader_options_for(d, nullptr);
  EXPECT_EQ(o.melt_on, Codes{"M3"});
  EXPECT_EQ(o.melt_off, Codes{"M5"});
  EXPECT_EQ(o.roller_down, Codes{"M60"});
  EXPECT_TRUE(o.roller_up.empty()) << "an empty code is no code";
  EXPECT_EQ(o.prime, Codes{"M70"});
  EXPECT_EQ(o.reverse_on, Codes{"M71"});
  EXPECT_EQ(o.reverse_off, Codes{"M72"});
  EXPECT_EQ(o.heat_on, Codes{"M80"});
  EXPECT_EQ(o.heat_off, Codes{"M81"});
  EXPECT_EQ(o.rpm_word, "Q");
  EXPECT_TRUE(o.inches);
  EXPECT_DOUBLE_EQ(o.rapid_feed_mm_s, 500);
  EXPECT_FALSE(o.dwell_p_seconds) << "the writer writes G4 P in milliseconds";
  EXPECT_FALSE(o.extruder.has_value());

  Extruder filament;
  filament.kind = ExtruderKind::kFilament;
  filament.filament_diameter_mm = 2.85;
  const ReaderOptions f = reader_options_for(GcodeDialect{}, &filament);
  ASSERT_TRUE(f.extruder.has_value());
  EXPECT_EQ(f.extruder->kind, ExtruderKind::kFilament);
  EXPECT_DOUBLE_EQ(f.filament_diameter_mm, 2.85);
  GcodeDialect no_speed;
  no_speed.rpm_word.clear();
  EXPECT_TRUE(reader_options_for(no_speed, nullptr).rpm_word.empty()) << "no speed words written, none read";

  Extruder pump;
  pump.displacement_mm3_per_rev = 10000;
  const ReaderOptions p = reader_options_for(GcodeDialect{}, &pump);
  ASSERT_TRUE(p.extruder.has_value());
  EXPECT_DOUBLE_EQ(p.extruder->displacement_mm3_per_rev, 10000);
  EXPECT_DOUBLE_EQ(p.filament_diameter_mm, ReaderOptions{}.filament_diameter_mm);
}

}  // namespace
}  // namespace beadtwin::gcode
