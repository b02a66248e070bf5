#include "gcode/lexer.hpp"

#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace beadtwin::gcode {
namespace {

TEST(GcodeReaderLexer, WordsCommentsLineNumbersAndChecksums) {
  const LexedLine a = lex_gcode_line("N10 g1 X10.5 y-2 Z+.5 F1800. ; TYPE:Perimeter \r", 7, "f.gcode");
  EXPECT_EQ(a.kind, LineKind::kPlain);
  EXPECT_EQ(a.block.line, 7);
  ASSERT_EQ(a.block.words.size(), 5u) << "N is dropped";
  const char letters[] = {'G', 'X', 'Y', 'Z', 'F'};
  const double values[] = {1, 10.5, -2, 0.5, 1800};
  const int columns[] = {5, 8, 14, 18, 23};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(a.block.words[i].letter, letters[i]);
    EXPECT_DOUBLE_EQ(a.block.words[i].value, values[i]);
    EXPECT_EQ(a.block.words[i].column, columns[i]);
  }
  ASSERT_EQ(a.block.comments.size(), 1u);
  EXPECT_EQ(a.block.comments[0], "TYPE:Perimeter");

  const LexedLine b = lex_gcode_line("(start) G0 X1 (middle (nested?) G1 X2", 1, "f");
  ASSERT_EQ(b.block.comments.size(), 2u);
  EXPECT_EQ(b.block.comments[0], "start");
  EXPECT_EQ(b.block.comments[1], "middle (nested?");
  ASSERT_EQ(b.block.words.size(), 4u) << "a comment ends at the first ')'";
  EXPECT_EQ(b.block.words[3].value, 2.0);

  const LexedLine c = lex_gcode_line("N3 T0*57", 3, "f");
  ASSERT_EQ(c.block.words.size(), 1u);
  EXPECT_EQ(c.block.words[0].letter, 'T');
  const LexedLine d = lex_gcode_line("N4 G1 X5*103 ; after the checksum", 4, "f");
  ASSERT_EQ(d.block.words.size(), 2u);
  EXPECT_EQ(d.block.words[1].value, 5.0);
  EXPECT_EQ(d.block.comments.size(), 1u);

  EXPECT_TRUE(lex_gcode_line("/G1 X5", 1, "f").block.block_delete);
  EXPECT_TRUE(lex_gcode_line("  / G1 X5", 1, "f").block.block_delete);
  EXPECT_FALSE(lex_gcode_line("G1 X5", 1, "f").block.block_delete);
  EXPECT_TRUE(lex_gcode_line("%", 1, "f").block.words.empty());
  EXPECT_TRUE(lex_gcode_line("", 1, "f").block.words.empty());

  const LexedLine msg = lex_gcode_line("M117 Printing 3 of 4 (x)", 1, "f");
  ASSERT_EQ(msg.block.words.size(), 1u) << "M117's text is a message, not words";
  EXPECT_EQ(msg.block.comments.at(0), "Printing 3 of 4 (x)");
  const LexedLine quoted = lex_gcode_line("M862.3 P \"MK3S\"", 1, "f");
  ASSERT_EQ(quoted.block.words.size(), 1u);
  EXPECT_DOUBLE_EQ(quoted.block.words[0].value, 862.3);
  EXPECT_FALSE(quoted.block.has('P')) << "P has a string, not a number";
}

TEST(GcodeReaderLexer, BadNumbersNameLineAndColumn) {
  const auto column_of = [](const std::string& text) {
    try {
      lex_gcode_line(text, 12, "bad.gcode");
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().line, 12);
      EXPECT_EQ(e.where().file, "bad.gcode");
      EXPECT_EQ(e.key(), "gcode");
      return e.where().column;
    }
    return -1;
  };
  EXPECT_EQ(column_of("G1 X1.2.3"), 8);
  EXPECT_EQ(column_of("G1 Xabc"), 5);
  EXPECT_EQ(column_of("G1 Y"), 5);
  EXPECT_EQ(column_of("G1 X--1"), 5);
  EXPECT_EQ(column_of("G1 X1 ! "), 7);
  EXPECT_EQ(column_of("G1 XY2"), 5);
  EXPECT_EQ(column_of("G1 X1 ; fine: X--"), -1);
}

TEST(GcodeReaderLexer, MacroLinesAreReportedNotLexed) {
  for (const char* line : {"#100=2.5", "G1 X#1 Y2", "G1 X[#1+2]", "IF [#1 GT 2] GOTO 10",
                           "WHILE [#1 LT 3] DO1", "END1", "GOTO 20", "N20 goto20"})
    EXPECT_EQ(lex_gcode_line(line, 1, "f").kind, LineKind::kMacro) << line;
  for (const char* line : {"G1 X1 (IF you must)", "G1 X1 ; #1 and [2]", "M117 IF only"})
    EXPECT_EQ(lex_gcode_line(line, 1, "f").kind, LineKind::kPlain) << line;
}

}  // namespace
}  // namespace beadtwin::gcode
