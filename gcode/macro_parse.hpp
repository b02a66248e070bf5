// The parsed form of a Fanuc Custom Macro B program (gcode/macro.hpp runs it). Parsing reads the whole text
// once, so every syntax error, unknown function, unbalanced bracket and unmatched DO/END is reported with its
// line and column before anything runs.
//
// The program is a list of lines; each holds at most one statement (an assignment, IF, GOTO, WHILE/DO, END or
// a block of address words) plus its comments. Expressions live in one node arena shared by all lines.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace beadtwin::gcode::macro {

// What an expression node computes; operands are nodes a and b.
enum class Op {
  kNumber,    // `number`
  kVariable,  // #`a` (a: the index expression)
  kNeg,       // -a
  kAdd,
  kSub,
  kMul,
  kDiv,
  kMod,
  kEq,
  kNe,
  kGt,
  kGe,
  kLt,
  kLe,
  kAnd,
  kOr,
  kXor,
  kFunction,  // `function`[a] or, for two arguments, [a, b]
};

enum class Function {
  kSin,
  kCos,
  kTan,
  kAsin,
  kAcos,
  kAtan,
  kAtan2,
  kSqrt,
  kAbs,
  kRound,
  kFix,
  kFup,
  kLn,
  kExp,
  kPow
};

// The name a program writes for `f` (ATAN for both arities).
const char* function_name(Function f);

// One node of an expression, in the arena Parsed::nodes.
struct Node {
  Op op = Op::kNumber;
  double number = 0;  // kNumber
  Function function = Function::kSin;
  int a = -1;      // first operand (node index)
  int b = -1;      // second operand
  int column = 0;  // 1-based column of the operator, function name or number, for run-time errors
};

// An address word whose value is an expression (`X#15`, `Y-#16`, `X[#1*2]`, `G1`).
struct AddressWord {
  char letter = 0;
  int column = 0;
  int value = -1;  // node
};

// What a line's statement is.
enum class Kind {
  kEmpty,    // blank, comment only, `%`, or a label alone
  kProgram,  // `O<number>`: starts a program
  kAssign,   // #target = value
  kIfGoto,   // IF [condition] GOTO value
  kIfThen,   // IF [condition] THEN #target = value
  kGoto,     // GOTO value
  kWhile,    // WHILE [condition] DO loop_id, or DO loop_id alone (condition -1: loops for ever)
  kEnd,      // END loop_id
  kWords,    // address words: a block for the machine, or M98/M99/M02/M30 for the interpreter
};

// One line of the text, parsed; expression fields are node indices (-1: none).
struct Line {
  int line = 0;               // 1-based line in the text
  bool block_delete = false;  // starts with `/`
  std::optional<long> label;  // N number
  Kind kind = Kind::kEmpty;
  int column = 0;                     // 1-based column where the statement starts
  long program_number = 0;            // kProgram
  int target = -1;                    // kAssign, kIfThen: node of the variable's index
  int target_column = 0;              // column of the `#` assigned to
  int value = -1;                     // kAssign, kIfThen: assigned value; kGoto, kIfGoto: the N to go to
  int condition = -1;                 // kIfGoto, kIfThen, kWhile
  int loop_id = 0;                    // kWhile, kEnd: the m of DO m / END m
  int partner = -1;                   // kWhile: index of its END line; kEnd: index of its WHILE/DO line
  std::vector<AddressWord> words;     // kWords
  std::vector<std::string> comments;  // `( )` and `;` comments, without the delimiters
};

// One program of the file: the lines between its O line (or the file's start) and the next O line.
struct Program {
  long number = -1;                         // -1: code before the first O line
  int o_line = 0;                           // 1-based line of the O word (0 for code before the first O line)
  int first = 0;                            // index of the first line after the O line
  int last = 0;                             // one past the program's last line
  std::map<long, std::vector<int>> labels;  // N number -> line indices
};

// A whole file, parsed.
struct Parsed {
  std::string file;
  std::vector<Node> nodes;
  std::vector<Line> lines;
  std::vector<Program> programs;  // programs[0] runs first
};

// Throws InputError naming `file_name`, line and column for a syntax error, an unknown word or function,
// unbalanced brackets or comments, a DO/END that does not match, or a program number given twice.
Parsed parse_macro_program(std::string_view text, const std::string& file_name);

}  // namespace beadtwin::gcode::macro
