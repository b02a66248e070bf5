#include <cmath>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "gcode/macro.hpp"

namespace beadtwin::gcode {
namespace {

std::vector<Block> run(std::string_view text, MacroOptions options = {}) {
  std::vector<Block> out;
  MacroProgram(text, std::move(options)).run([&](const Block& b) { out.push_back(b); });
  return out;
}

// The value of `expression` as the program computes it: assigned to #100 and written as X#100.
double value_of(const std::string& expression) {
  const std::vector<Block> blocks = run("#100 = " + expression + "\nX#100\n");
  if (blocks.size() != 1 || !blocks[0].has('X')) {
    ADD_FAILURE() << "no X block for " << expression;
    return NAN;
  }
  return *blocks[0].get('X');
}

// The InputError the program throws when parsed or run.
InputError error_of(std::string_view text, MacroOptions options = {}) {
  options.file_name = "part.nc";
  try {
    run(text, std::move(options));
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError from:\n" << text;
  return InputError("none");
}

// The words of `b` as text ("G1 X2 Y-3"), for comparing whole blocks.
std::string words(const Block& b) {
  std::string s;
  for (const Word& w : b.words) {
    if (!s.empty()) s += ' ';
    s += w.letter;
    const double r = std::round(w.value * 1000) / 1000;
    std::string v = std::to_string(r);
    v.erase(v.find_last_not_of('0') + 1);
    if (v.back() == '.') v.pop_back();
    s += v;
  }
  return s;
}

std::vector<std::string> all_words(const std::vector<Block>& blocks) {
  std::vector<std::string> out;
  for (const Block& b : blocks)
    if (!b.words.empty()) out.push_back(words(b));
  return out;
}

using Texts = std::vector<std::string>;

TEST(Macro, ExpressionPrecedenceAndBrackets) {
  EXPECT_EQ(value_of("1 + 2 * 3"), 7);
  EXPECT_EQ(value_of("[1 + 2] * 3"), 9);
  EXPECT_EQ(value_of("-2 * 3 + 10"), 4);
  EXPECT_EQ(value_of("10 - 4 - 3"), 3);  // left to right
  EXPECT_EQ(value_of("16 / 4 / 2"), 2);
  EXPECT_EQ(value_of("2*[3+[4-1]*2]"), 18);
  EXPECT_EQ(value_of("-[2 + 3]"), -5);
  EXPECT_EQ(value_of("7 MOD 3 + 1"), 2);
  EXPECT_EQ(value_of("1 + 2 EQ 3"), 1);  // comparisons looser than arithmetic
  EXPECT_EQ(value_of("[1 LT 2] AND [3 GT 4]"), 0);
  EXPECT_EQ(value_of("[1 LT 2] OR [3 GT 4]"), 1);
  EXPECT_EQ(value_of("1 LT 2 AND 4 GT 3"), 1);  // AND looser than comparisons
  EXPECT_EQ(value_of("[1 LT 2] XOR [2 LT 3]"), 0);
  EXPECT_EQ(value_of("12 AND 10"), 8);  // bitwise on whole numbers
  EXPECT_EQ(value_of("0.1 + 0.2 EQ 0.3"), 1);
  EXPECT_EQ(value_of("3 GE 3.0000000000001"), 1);
  EXPECT_EQ(value_of("3 GT 3.0000000000001"), 0);
  EXPECT_EQ(value_of(".5 + 5."), 5.5);
  EXPECT_EQ(value_of("[[2]]*[-[-3]]"), 6);
}

TEST(Macro, FunctionsWorkInDegrees) {
  EXPECT_EQ(value_of("SIN[30]"), 0.5);
  EXPECT_EQ(value_of("SIN[390]"), 0.5);
  EXPECT_EQ(value_of("SIN[-30]"), -0.5);
  EXPECT_EQ(value_of("COS[60]"), 0.5);
  EXPECT_EQ(value_of("COS[90]"), 0.0);
  EXPECT_EQ(value_of("SIN[180]"), 0.0);
  EXPECT_EQ(value_of("COS[180]"), -1.0);
  EXPECT_NEAR(value_of("SIN[12.5]"), std::sin(12.5 * std::numbers::pi / 180), 1e-15);
  EXPECT_NEAR(value_of("TAN[45]"), 1.0, 1e-15);
  EXPECT_NEAR(value_of("ATAN[1]"), 45.0, 1e-12);
  EXPECT_NEAR(value_of("ATAN[1]/[-1]"), 135.0, 1e-12);
  EXPECT_NEAR(value_of("ATAN[-1]/[-1]"), 225.0, 1e-12);
  EXPECT_NEAR(value_of("ATAN[-1, 1]"), 315.0, 1e-12);
  EXPECT_NEAR(value_of("ASIN[0.5]"), 30.0, 1e-12);
  EXPECT_NEAR(value_of("ACOS[0]"), 90.0, 1e-12);
  EXPECT_EQ(value_of("SQRT[16]"), 4);
  EXPECT_EQ(value_of("ABS[-3]"), 3);
  EXPECT_EQ(value_of("ROUND[2.5]"), 3);
  EXPECT_EQ(value_of("ROUND[-2.5]"), -3);
  EXPECT_EQ(value_of("FIX[1.7]"), 1);
  EXPECT_EQ(value_of("FIX[-1.7]"), -1);
  EXPECT_EQ(value_of("FUP[1.2]"), 2);
  EXPECT_EQ(value_of("FUP[-1.2]"), -2);
  EXPECT_NEAR(value_of("LN[EXP[2]]"), 2.0, 1e-15);
  EXPECT_EQ(value_of("POW[2, 10]"), 1024);
  EXPECT_EQ(value_of("sqrt[9] + abs[-1]"), 4);  // lower case
}

TEST(Macro, VacantVariableDropsTheWordButCountsZeroInArithmetic) {
  const std::vector<Block> blocks =
      run("G1 X#1 Y5 Z#2\n"
          "#3 = #1 + 2\n"
          "G1 X#3\n"
          "#4 = #1\n"  // copies the vacancy
          "G1 X#4 Y1\n"
          "#5 = #1 * 5\n"  // a number: 0
          "G1 X#5\n"
          "IF [#1 EQ #0] THEN #6 = 1\n"
          "IF [#1 EQ 0] THEN #7 = 1\n"
          "IF [#1 GE 0] THEN #8 = 1\n"
          "G1 A#6 B#7 C#8\n"
          "X-#1 Y[#1]\n"  // signs and brackets keep it vacant: nothing to emit
          "X[#1 + 0] Y#1\n");
  EXPECT_EQ(all_words(blocks), (Texts{"G1 Y5", "G1 X2", "G1 Y1", "G1 X0", "G1 A1 C1", "X0"}));
}

TEST(Macro, IfGotoJumpsForwardAndBackward) {
  const std::vector<Block> blocks =
      run("#1 = 0\n"
          "N10 #1 = #1 + 1\n"
          "G1 X#1\n"
          "IF [#1 LT 3] GOTO 10\n"  // backward
          "IF [#1 EQ 3] GOTO 30\n"  // forward
          "G1 Y99\n"
          "N30 G1 Z1\n"
          "#2 = 50\n"
          "GOTO #2\n"  // computed
          "G1 Y98\n"
          "N50 M30\n"
          "G1 Y97\n");
  EXPECT_EQ(all_words(blocks), (Texts{"G1 X1", "G1 X2", "G1 X3", "G1 Z1", "M30"}));
}

TEST(Macro, IfThenAssignsOnlyWhenTrue) {
  const std::vector<Block> blocks =
      run("#1 = 5\n"
          "IF [#1 GT 3] THEN #2 = #1 * 2\n"
          "IF [#1 LT 3] THEN #3 = 1\n"
          "IF [[#1 GT 3] AND [#1 LT 10]] THEN #4 = 7\n"
          "G1 X#2 Y#3 Z#4\n");
  EXPECT_EQ(all_words(blocks), (Texts{"G1 X10 Z7"}));
}

TEST(Macro, NestedWhileLoops) {
  const std::vector<Block> blocks =
      run("#1 = 0\n"
          "WHILE [#1 LT 3] DO 1\n"
          "  #2 = 0\n"
          "  WHILE [#2 LT 2] DO 2\n"
          "    G1 X#1 Y#2\n"
          "    #2 = #2 + 1\n"
          "  END 2\n"
          "  #1 = #1 + 1\n"
          "END 1\n"
          "WHILE [#1 LT 0] DO 1\n"  // false at once: the body never runs
          "G1 Z99\n"
          "END 1\n"
          "#5 = 0\n"
          "#6 = 0\n"
          "WHILE [#5 LE 0.3] DO 3\n"  // 0, 0.1, 0.2, 0.30000000000000004: four passes
          "#6 = #6 + 1\n"
          "#5 = #5 + 0.1\n"
          "END 3\n"
          "G1 Z#6\n");
  EXPECT_EQ(all_words(blocks),
            (Texts{"G1 X0 Y0", "G1 X0 Y1", "G1 X1 Y0", "G1 X1 Y1", "G1 X2 Y0", "G1 X2 Y1", "G1 Z4"}));
  EXPECT_EQ(blocks[2].line, 5);
}

TEST(Macro, SubprogramCallsRepeatAndReturn) {
  const std::string text =
      "%\n"
      "O1000 (MAIN)\n"
      "G1 X1\n"
      "G1 X1.5 M98 P2000 L3\n"
      "G1 X2 Y#1\n"  // #1 set by the subprogram: M98 shares the locals
      "M98 P2000\n"
      "M98 P3000\n"
      "N70 G1 X7\n"
      "M30\n"
      "%\n"
      "O2000\n"
      "#100 = #100 + 1\n"
      "#1 = 42\n"
      "G1 Y#100\n"
      "M99\n"
      "O3000\n"
      "G1 Z3\n"
      "M99 P70\n"  // back to N70 of the caller
      "%\n";
  const std::vector<Block> blocks = run(text);
  EXPECT_EQ(all_words(blocks), (Texts{"G1 X1", "G1 X1.5", "G1 Y1", "G1 Y2", "G1 Y3", "G1 X2 Y42", "G1 Y4",
                                      "G1 Z3", "G1 X7", "M30"}));
  // The main program's comment on its O line is not a block; the subprogram's blocks carry their own lines.
  EXPECT_EQ(blocks[2].line, 14);

  const InputError missing = error_of("M98 P4000\nM30\n");
  EXPECT_EQ(missing.where().line, 1);
  EXPECT_EQ(missing.where().column, 5);
  EXPECT_NE(missing.message().find("no program O4000"), std::string::npos) << missing.what();

  const InputError recursive = error_of("O1\nM98 P2\nO2\nM98 P2\nM99\n");
  EXPECT_EQ(recursive.where().line, 4);
  EXPECT_NE(recursive.message().find("nested more than"), std::string::npos) << recursive.what();

  const InputError no_return = error_of("O1\nM98 P2\nM30\nO2\nG1 X1\n");
  EXPECT_EQ(no_return.where().line, 4);
  EXPECT_NE(no_return.message().find("without M99"), std::string::npos) << no_return.what();
}

TEST(Macro, IndirectVariables) {
  const std::vector<Block> blocks =
      run("#1 = 5\n"
          "#[#1 + 100] = 7\n"
          "G1 X#105\n"
          "#2 = #[100 + #1]\n"
          "G1 Y#2\n"
          "#[#1 * 2] = 3\n"
          "G1 Z#10 A#[#1 * 2] B#[#1 + 994]\n");
  EXPECT_EQ(all_words(blocks), (Texts{"G1 X7", "G1 Y7", "G1 Z3 A3"}));

  const InputError outside = error_of("#1 = 2000\nG1 X#[#1]\n");
  EXPECT_EQ(outside.where().line, 2);
  EXPECT_EQ(outside.where().column, 5);
  EXPECT_NE(outside.message().find("#2000 is not a variable"), std::string::npos) << outside.what();
  EXPECT_NE(error_of("#[1.5] = 2\n").message().find("whole number"), std::string::npos);
}

TEST(Macro, ErrorsNameFileLineAndColumn) {
  struct Case {
    std::string text;
    int line;
    int column;
    std::string says;
  };
  const Case cases[] = {
      {"G1 X10\n#1 = 2 + * 3\n", 2, 10, "expected a number"},
      {"G1 X10\n#1 = FOO[2]\n", 2, 6, "unknown function"},
      {"#1 = [2 + 3\n", 1, 6, "not closed"},
      {"#1 = 2 + 3]\n", 1, 11, "']' without '['"},
      {"#1 = SIN[30\n", 1, 9, "not closed"},
      {"G1 X10 (open comment\n", 1, 8, "not closed"},
      {"G1 XY\n", 1, 4, "unknown word"},
      {"G1 X\n", 1, 5, "needs a value"},
      {"G1 X10\nFROB 3\n", 2, 1, "unknown word 'FROB'"},
      {"IF [1 EQ 1] #1 = 2\n", 1, 13, "GOTO or THEN"},
      {"G1\nEND 1\n", 2, 1, "END 1 without a DO 1"},
      {"WHILE [1 EQ 1] DO 1\nG1 X1\n", 1, 1, "has no END 1"},
      {"WHILE [1] DO 1\nWHILE [1] DO 2\nEND 1\nEND 2\n", 3, 1, "loops must nest"},
      {"WHILE [1] DO 1\nWHILE [1] DO 1\nEND 1\nEND 1\n", 2, 1, "already open"},
      {"WHILE [1] DO 4\nEND 4\n", 1, 14, "1, 2 or 3"},
      {"G1\nGOTO 99\n", 2, 6, "no N99"},
      {"N5 G1\nN5 G2\nGOTO 5\n", 3, 6, "labels lines 1 and 2"},
      {"#1 = 0\n#2 = 5 / #1\n", 2, 8, "division by zero"},
      {"#2 = 5 MOD 0\n", 1, 8, "MOD 0"},
      {"#1 = 1\nG1 X[SQRT[-#1]]\n", 2, 6, "SQRT[-1]"},
      {"#1 = LN[0]\n", 1, 6, "LN[0]"},
      {"#0 = 1\n", 1, 1, "always vacant"},
      {"#3000 = 12 (RADIUS MUST BE POSITIVE)\n", 1, 1, "alarm #3000 = 12: RADIUS MUST BE POSITIVE"},
      {"O1\nG1\nO1\n", 3, 1, "already defined"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const InputError e = error_of(c.text);
    EXPECT_EQ(e.where().file, "part.nc");
    EXPECT_EQ(e.where().line, c.line);
    EXPECT_EQ(e.where().column, c.column);
    EXPECT_NE(e.message().find(c.says), std::string::npos) << e.what();
  }
  EXPECT_EQ(std::string(error_of("G1 X10\n#1 = 2 + * 3\n").what()).rfind("part.nc:2:10: ", 0), 0u);
}

TEST(Macro, StepLimitStopsAnEndlessLoop) {
  MacroOptions options;
  options.max_steps = 1000;
  const std::string endless =
      "#1 = 0\n"
      "WHILE [1 EQ 1] DO 1\n"
      "#1 = #1 + 1\n"
      "G1 X#1\n"
      "END 1\n"
      "M30\n";
  const InputError e = error_of(endless, options);
  EXPECT_EQ(e.where().line, 2);
  EXPECT_NE(e.message().find("program did not finish after 1000 steps (WHILE at line 2"), std::string::npos)
      << e.what();

  const InputError by_goto = error_of("G1\nN1 G1 X1\nG1 X2\nGOTO 1\n", options);
  EXPECT_EQ(by_goto.where().line, 4);
  EXPECT_NE(by_goto.message().find("GOTO at line 4"), std::string::npos) << by_goto.what();

  // The same loop with an end finishes well inside the limit.
  const std::string bounded =
      "#1 = 0\n"
      "WHILE [#1 LT 100] DO 1\n"
      "#1 = #1 + 1\n"
      "G1 X#1\n"
      "END 1\n"
      "M30\n";
  EXPECT_EQ(run(bounded, options).size(), 101u);
}

TEST(Macro, BlockDeleteCommentsAndColumns) {
  const std::string text =
      "/G1 X1\n"
      "/#1 = 5\n"
      "G1 X2 Y#1 (MOVE) ; the rest\n"
      "(A NOTE)\n"
      "n7 g1 x3\n";
  const std::vector<Block> on = run(text);
  ASSERT_EQ(on.size(), 3u);
  EXPECT_EQ(words(on[0]), "G1 X2");
  EXPECT_EQ(on[0].line, 3);
  EXPECT_EQ(on[0].comments, (Texts{"MOVE", "the rest"}));
  EXPECT_EQ(on[0].words[1].column, 4);
  EXPECT_TRUE(on[1].words.empty());
  EXPECT_EQ(on[1].comments, (Texts{"A NOTE"}));
  EXPECT_EQ(words(on[2]), "G1 X3");  // N is a label, not a word; lower case reads as upper
  EXPECT_EQ(on[2].words[0].column, 4);

  MacroOptions off;
  off.block_delete = false;
  const std::vector<Block> all = run(text, off);
  ASSERT_EQ(all.size(), 4u);
  EXPECT_EQ(words(all[0]), "G1 X1");
  EXPECT_TRUE(all[0].block_delete);
  EXPECT_EQ(words(all[1]), "G1 X2 Y5");
  EXPECT_FALSE(all[1].block_delete);
}

// Program O2023 of seed 002 (Table 3) as its PDF text reconstructs: a cylinder of radius 50 printed in layers
// of 0.5 mm up to Z 20, each layer an upper semicircle swept from 180° down to 0° in steps of 2° with the
// feed rising by 5 from 100 at every step, then a lower semicircle from 0° to 180° (Y = -R sin) with the feed
// falling by 5 again; the wall is thicker where the feed is slower. M27 starts the heating and M23 the
// filament feed at every layer; M24 and M28 stop them at the end. (The table has M02 before M24/M28, which
// would end the program before them; here they come before M30.)
constexpr const char* kO2023 = R"(%
O2023 (R=50 ON A CIRCLE)
N5 T2 M06 (PRINT HEAD CALL)
N6 G0 G54 G90 G80 G18 (WORK SYSTEM SETTING, WORK PLAN, ABSOLUTE PROGRAMMING)
N10 #1=0.5 (START [Z])
N20 #2=20 (END [Z])
N30 #3=0.5 (INCREMENT ON [Z])
N40 WHILE [#1LE#2] DO 2
(UPPER SEMICIRCLE)
N50 #10=50 (RADIUS OF SEMICIRCLE)
N60 #11=180 (STARTING ANGLE)
N70 #12=0 (END ANGLE)
N80 #13=2 (ANGULAR INCREMENT)
N90 #17=100 (STARTING FEED)
N100 #18=5 (FEED INCREMENT)
N110 G0 G18 X-50 Y0 M27 (START HEATING)
N120 G1 Z#1 F1000 M23 (FILAMENT FEED START)
N130 WHILE [#11GE#12] DO 1
N140 #15=#10*COS[#11]
N150 #16=#10*SIN[#11]
N160 G1 X#15 Y#16 F#17
N170 #11=#11-#13
N180 #17=#17+#18
N190 END 1
(LOWER HALF CIRCLE)
N200 #10=50 (RADIUS OF SEMICIRCLE)
N210 #11=0 (STARTING ANGLE)
N220 #12=180 (END ANGLE)
N230 #13=2 (ANGULAR INCREMENT)
N240 #18=5 (FEED INCREMENT)
N250 G0 G18 X50 Y0
N260 G1 Z#1 F1000
N270 WHILE [#11LE#12] DO 1
N280 #15=#10*COS[#11]
N290 #16=-#10*SIN[#11]
N300 G1 X#15 Y#16 F#17
N310 #11=#11+#13
N320 #17=#17-#18
N330 END 1
N340 #1=#1+#3
N350 END 2
N360 M24 (FILAMENT FEED STOP)
N370 M28 (HEATING OFF)
N380 M30
%
)";

// 1-based line of the text that starts with `start`.
int line_of(std::string_view text, std::string_view start) {
  int line = 1;
  for (std::size_t at = 0; at < text.size(); ++line) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    if (text.substr(at, end - at).starts_with(start)) return line;
    at = end + 1;
  }
  ADD_FAILURE() << "no line starts with " << start;
  return 0;
}

bool has_m(const Block& b, double code) {
  for (const Word& w : b.words)
    if (w.letter == 'M' && w.value == code) return true;
  return false;
}

TEST(Macro, O2023PrintsACylinderWithVariableFeed) {
  const std::string_view text = kO2023;
  const std::vector<Block> blocks = run(text);
  std::vector<Block> moves;  // blocks with words; comment-only blocks counted apart
  int upper_comments = 0;
  for (const Block& b : blocks) {
    if (!b.words.empty())
      moves.push_back(b);
    else if (b.comments == Texts{"UPPER SEMICIRCLE"})
      ++upper_comments;
  }
  constexpr int kLayers = 40;  // Z 0.5, 1.0, ... 20
  constexpr int kSteps = 91;   // 180°, 178°, ... 0°
  constexpr double kR = 50;
  EXPECT_EQ(upper_comments, kLayers);
  ASSERT_EQ(moves.size(), 2u + kLayers * (4u + 2u * kSteps) + 3u);

  std::size_t i = 0;
  EXPECT_EQ(words(moves[i]), "T2 M6");
  EXPECT_EQ(words(moves[++i]), "G0 G54 G90 G80 G18");
  const auto expect_on_circle = [&](const Block& b, double angle_deg, double feed) {
    const double a = angle_deg * std::numbers::pi / 180;
    ASSERT_TRUE(b.has('X') && b.has('Y') && b.has('F')) << words(b);
    EXPECT_EQ(b.get('G'), 1.0);
    EXPECT_NEAR(std::hypot(*b.get('X'), *b.get('Y')), kR, 1e-9);
    EXPECT_NEAR(*b.get('X'), kR * std::cos(a), 1e-9) << angle_deg;
    EXPECT_NEAR(*b.get('Y'), kR * std::sin(a), 1e-9) << angle_deg;
    EXPECT_EQ(*b.get('F'), feed) << angle_deg;
  };
  const int upper_line = line_of(text, "N160");
  const int lower_line = line_of(text, "N300");
  for (int layer = 0; layer < kLayers; ++layer) {
    SCOPED_TRACE(layer);
    const double z = 0.5 * (layer + 1);
    const Block& heat = moves[++i];
    EXPECT_EQ(heat.line, line_of(text, "N110"));
    EXPECT_TRUE(has_m(heat, 27)) << words(heat);
    EXPECT_EQ(heat.get('X'), -kR);
    const Block& start = moves[++i];
    EXPECT_EQ(start.line, line_of(text, "N120"));
    EXPECT_TRUE(has_m(start, 23)) << words(start);
    EXPECT_EQ(start.get('Z'), z);
    for (int k = 0; k < kSteps; ++k) {
      const Block& b = moves[++i];
      EXPECT_EQ(b.line, upper_line);
      expect_on_circle(b, 180.0 - 2.0 * k, 100.0 + 5.0 * k);
    }
    EXPECT_EQ(words(moves[++i]), "G0 G18 X50 Y0");
    const Block& lower_start = moves[++i];
    EXPECT_EQ(lower_start.line, line_of(text, "N260"));
    EXPECT_EQ(lower_start.get('Z'), z);
    EXPECT_EQ(lower_start.get('F'), 1000.0);
    for (int k = 0; k < kSteps; ++k) {
      const Block& b = moves[++i];
      EXPECT_EQ(b.line, lower_line);
      // the feed goes on from where the upper semicircle left it (100 + 5 * 91) and falls by 5 a step
      expect_on_circle(b, -2.0 * k, 555.0 - 5.0 * k);
    }
  }
  EXPECT_EQ(moves[2].words[2].column, 13);  // "N110 G0 G18 X-50": X at column 13
  EXPECT_EQ(words(moves[++i]), "M24");
  EXPECT_EQ(moves[i].line, line_of(text, "N360"));
  EXPECT_EQ(words(moves[++i]), "M28");
  EXPECT_EQ(words(moves[++i]), "M30");
  // No M23, M24, M27 or M28 anywhere else.
  int m23 = 0, m24 = 0, m27 = 0, m28 = 0;
  for (const Block& b : moves) {
    m23 += has_m(b, 23);
    m24 += has_m(b, 24);
    m27 += has_m(b, 27);
    m28 += has_m(b, 28);
  }
  EXPECT_EQ(m23, kLayers);
  EXPECT_EQ(m27, kLayers);
  EXPECT_EQ(m24, 1);
  EXPECT_EQ(m28, 1);
}

}  // namespace
}  // namespace beadtwin::gcode
