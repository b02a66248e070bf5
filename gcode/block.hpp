// One block (line) of a G-code program as its words, the common currency of the plain G-code lexer and the
// Fanuc macro interpreter: both hand blocks with their source line to the reader that turns them into a
// Toolpath. Values are numbers already (a macro's expressions evaluated); letters are upper case.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace beadtwin::gcode {

// A letter and its number.
struct Word {
  char letter = 0;   // 'G', 'X', 'M', ... (upper case)
  double value = 0;  // the number, as written or as a macro expression evaluated
  int column = 0;    // 1-based column of the letter in the source line (0 when generated)
};

struct Block {
  int line = 0;                       // 1-based line in the source program
  std::vector<Word> words;            // in the order written
  std::vector<std::string> comments;  // text of `;` and `( )` comments, without the delimiters
  bool block_delete = false;          // the line starts with `/` (skipped when block delete is on)

  // The value of the first word with `letter`, if any.
  std::optional<double> get(char letter) const {
    for (const Word& w : words)
      if (w.letter == letter) return w.value;
    return std::nullopt;
  }
  bool has(char letter) const { return get(letter).has_value(); }
};

}  // namespace beadtwin::gcode
