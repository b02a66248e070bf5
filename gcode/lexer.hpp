// The plain G-code lexer: one line of program text into one Block (gcode/block.hpp) of words and
// comments, for read_gcode (gcode/program_reader.hpp).
//
// What a line may hold:
//   words        a letter and a number, `G1`, `X-12.5`, `F1800`, `M862.3`; letters in either case (kept upper
//                case), spaces allowed between the letter and its number; no exponents
//   comments     `; to the end of the line` and `(in parentheses)`, kept as text without the delimiters and
//                the spaces around it (slicer annotations such as `;TYPE:Perimeter` or `;LAYER:3` are read
//                from there); a `(` never closed runs to the end of the line
//   N numbers    line numbers, dropped
//   checksums    `*` and the number after it (RepRap serial lines), dropped
//   block delete `/` as the line's first character: Block::block_delete
//   tape marker  `%` as the line's first character: the rest of the line is ignored
//   strings      `"..."` (Marlin parameters such as `M862.3 P "MK3S"`) and the free text after M117 or
//                M118 (display messages), kept as comments
// A line with macro syntax, `#` or `[` outside comments or a keyword IF, WHILE, GOTO, DO or END, is not
// lexed: the lexer says so (LineKind::kMacro) and the caller hands the program to the macro interpreter.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "gcode/block.hpp"

namespace beadtwin::gcode {

enum class LineKind : std::uint8_t {
  kPlain,  // words and comments, lexed into the block
  kMacro,  // macro syntax (variables, expressions, branches): block holds only the line number
};

// A lexed line: its kind, and its block when it is plain.
struct LexedLine {
  LineKind kind = LineKind::kPlain;
  Block block;
};

// Lexes `text` (one line, without its newline; a trailing carriage return is ignored), line `line` (1-based)
// of `file_name`. Throws InputError (key "gcode") naming the line and the 1-based column of a malformed
// number, a letter without a number, or a character no G-code line holds.
LexedLine lex_gcode_line(std::string_view text, int line, const std::string& file_name);

// The same into `block`, which the caller keeps from line to line so that its vectors' memory is reused
// (read_gcode lexes every line so): `block` is overwritten, and holds only the line number when the line
// is a macro line.
LineKind lex_gcode_line(std::string_view text, int line, const std::string& file_name, Block& block);

}  // namespace beadtwin::gcode
