// A Fanuc Custom Macro B interpreter: runs a parameterised print program (variables, WHILE loops, IF/GOTO,
// subprogram calls) and hands each block it reaches to the caller with its words evaluated to numbers, the
// way a Fanuc control feeds its motion planner. The programs of seed 002 (section 2.7, Tables 2-3: O2023 and
// O2024, a cylinder whose wall thickness follows the feed, which changes at every step of the semicircle)
// are written this way: the control computes X = #10*COS[#11], Y = #10*SIN[#11] and F#17 as it runs.
//
// The language:
//   variables   #1-#33 local, #100-#199 and #500-#999 common; every one vacant when a run starts. #0 is
//               always vacant. #[expr] is indirect. Assigning #3000 raises an alarm (an InputError with the
//               value and the line's comment), as a program checking its parameters does.
//   vacant      In arithmetic, functions and GT/GE/LT/LE a vacant variable counts 0; EQ/NE tell vacant from
//               0 (#1 EQ #0 is true only when #1 is vacant). Brackets or a sign around a variable keeps it
//               vacant, any operator or function makes it a number: `#2 = #1` and `#2 = -#1` copy the
//               vacancy, `#2 = #1 + 0` is 0. An address whose value is vacant is left out of the block
//               (`G1 X#1 Y5` with #1 vacant moves Y only).
//   expressions [ ] for grouping; + - * / MOD; EQ NE GT GE LT LE; AND OR XOR; functions SIN COS TAN ASIN
//               ACOS ATAN (ATAN[y]/[x] and ATAN[y, x] give 0-360°, ATAN[t] -90-90°) SQRT ABS ROUND FIX FUP LN
//               EXP POW[x, y]. Angles in degrees. ROUND rounds half away from 0; FIX and FUP round towards
//               and away from 0. Loosest first: OR XOR, AND, comparisons, + -, * / MOD, unary minus. (Fanuc
//               ranks AND with * and OR with +; a program that brackets each comparison, as Fanuc programs
//               must, means the same either way.) AND OR XOR work bitwise on whole numbers, so on
//               comparisons (1 or 0) they are logical. Comparisons treat numbers within 1e-9 (relative to
//               the larger, at least 1) as equal, so a loop stepping by 0.1 still reaches its end value.
//   statements  `#i = expr`; `IF [c] GOTO n`; `IF [c] THEN #i = expr`; `GOTO n` (to the line labelled N n
//               in the current program); `WHILE [c] DO m` ... `END m` and `DO m` ... `END m` (for ever),
//               m = 1, 2, 3, nested with different m; `M98 P<o> L<count>` runs O<o> of the same file count
//               times (subprogram calls share the local variables, as Fanuc's M98 does; at most 10 deep);
//               `M99` returns (`M99 P<n>` to N n of the caller); M99 in the main program, M02 and M30 end
//               the run; reaching the end of the main program ends it too.
//   blocks      Address words (a letter and a number, #variable or [expression], each with an optional sign:
//               `X#15`, `Y-#16`, `X[#1*2]`); `N` numbers label lines and are not words; `O` starts a program
//               (the code before the first O line, or else the first O program, runs first); `%` lines are
//               ignored; `( )` and `;` comments go to Block::comments; a line starting with `/` (or /1-/9)
//               is skipped when MacroOptions::block_delete is on. Letters may be lower case; spaces are
//               ignored between words and around operators.
//
// The emitted blocks: every line of address words the run reaches, words in the order written with their
// columns, and every comment-only line. M98 with its P and L, and M99 with its P, are the interpreter's and
// are left out of the block (the block's other words are emitted before the call). M02 and M30 are emitted.
// Macro statements (assignments, IF, WHILE, END, GOTO) are not emitted, nor their comments. Values are not
// rounded to the control's increment.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "gcode/block.hpp"

namespace beadtwin::gcode {

namespace macro {
struct Parsed;
}

// How a macro program is run.
struct MacroOptions {
  long max_steps = 10'000'000;  // lines executed before a run is stopped as endless
  std::string file_name;        // named in errors
  bool block_delete = true;     // skip lines that start with `/`
};

class MacroProgram {
 public:
  // Parses the whole program text. Throws InputError naming the file, line and column for a syntax error, an
  // unknown word or function, unbalanced brackets or comments, a DO without its END or an END without its DO,
  // or a program number given twice.
  explicit MacroProgram(std::string_view text, MacroOptions options = {});
  ~MacroProgram();
  MacroProgram(MacroProgram&&) noexcept;
  MacroProgram& operator=(MacroProgram&&) noexcept;

  // Runs the program from its start with every variable vacant, calling `emit` for each block reached, in
  // order. Throws InputError naming the line (and column where one applies) for a GOTO to a missing or
  // repeated N, an M98 to a missing program, a subprogram that ends without M99, division by zero, MOD 0,
  // SQRT or LN out of range, a variable outside the ranges above, a #3000 alarm, or more than
  // MacroOptions::max_steps lines executed (naming the loop that was still going round). Blocks emitted
  // before an error stay emitted.
  void run(const std::function<void(const Block&)>& emit) const;

 private:
  std::unique_ptr<const macro::Parsed> parsed_;
  MacroOptions options_;
};

}  // namespace beadtwin::gcode
