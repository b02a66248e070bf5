#include "gcode/macro_parse.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <utility>

#include <fmt/format.h>

#include "core/error.hpp"

namespace beadtwin::gcode::macro {

namespace {

struct FunctionName {
  const char* name;
  Function function;
};

// ATAN is both kAtan and kAtan2: the parser picks by the number of arguments.
constexpr FunctionName kFunctions[] = {
    {"SIN", Function::kSin},   {"COS", Function::kCos},   {"TAN", Function::kTan},
    {"ASIN", Function::kAsin}, {"ACOS", Function::kAcos}, {"ATAN", Function::kAtan},
    {"SQRT", Function::kSqrt}, {"ABS", Function::kAbs},   {"ROUND", Function::kRound},
    {"FIX", Function::kFix},   {"FUP", Function::kFup},   {"LN", Function::kLn},
    {"EXP", Function::kExp},   {"POW", Function::kPow},
};

bool is_letter(char c) {
  return c >= 'A' && c <= 'Z';
}
bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

// A line with its comments taken out: `code` keeps every column (comments become spaces) and is upper case.
struct SplitLine {
  std::string code;
  std::vector<std::string> comments;
};

std::string trimmed(std::string_view s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t");
  return std::string(s.substr(first, last - first + 1));
}

// Reads one line: comments out, the rest upper case. Throws for a `(` without `)` and a `)` without `(`.
class LineParser {
 public:
  LineParser(std::string_view raw, int line_number, const std::string& file, std::vector<Node>& nodes)
      : line_number_(line_number), file_(file), nodes_(nodes) {
    split_comments(raw);
  }

  Line parse() {
    Line l;
    l.line = line_number_;
    l.comments = std::move(comments_);
    skip_spaces();
    if (at_end() || peek() == '%') return l;  // `%` marks the tape's start and end
    if (peek() == '/') {
      l.block_delete = true;
      ++pos_;
      if (!at_end() && is_digit(peek())) ++pos_;  // optional block skip /1 ... /9: all alike here
      skip_spaces();
    }
    if (!at_end() && peek() == 'O' && letters_at(pos_).size() == 1) {
      l.kind = Kind::kProgram;
      l.column = column();
      ++pos_;
      l.program_number = parse_integer("a program number after O");
      expect_end();
      return l;
    }
    if (!at_end() && peek() == 'N' && letters_at(pos_).size() == 1) {
      ++pos_;
      l.label = parse_integer("a sequence number after N");
      skip_spaces();
    }
    if (at_end()) return l;
    l.column = column();
    if (peek() == '#') {
      l.kind = Kind::kAssign;
      parse_assignment_into(l);
    } else if (const std::string word = letters_at(pos_); word.size() > 1) {
      parse_keyword(word, l);
    } else {
      l.kind = Kind::kWords;
      parse_words(l);
    }
    expect_end();
    return l;
  }

 private:
  [[noreturn]] void fail(int column, const std::string& message) const {
    throw InputError({file_, line_number_, column}, {}, message);
  }
  [[noreturn]] void fail_here(const std::string& message) const { fail(column(), message); }

  void split_comments(std::string_view raw) {
    code_.assign(raw.size(), ' ');
    for (std::size_t i = 0; i < raw.size(); ++i) {
      const char c = raw[i];
      if (c == '(') {
        const auto close = raw.find(')', i + 1);
        if (close == std::string_view::npos)
          fail(static_cast<int>(i) + 1, "comment '(' is not closed by ')' on this line");
        comments_.push_back(trimmed(raw.substr(i + 1, close - i - 1)));
        i = close;
      } else if (c == ';') {
        comments_.push_back(trimmed(raw.substr(i + 1)));
        break;
      } else if (c == ')') {
        fail(static_cast<int>(i) + 1, "')' without '(' before it");
      } else {
        code_[i] = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      }
    }
  }

  int column() const { return static_cast<int>(pos_) + 1; }
  bool at_end() const { return pos_ >= code_.size(); }
  char peek() const { return at_end() ? '\0' : code_[pos_]; }
  void skip_spaces() {
    while (!at_end() && (code_[pos_] == ' ' || code_[pos_] == '\t' || code_[pos_] == '\r')) ++pos_;
  }
  // The run of letters starting at `at` (empty when none).
  std::string letters_at(std::size_t at) const {
    std::size_t end = at;
    while (end < code_.size() && is_letter(code_[end])) ++end;
    return code_.substr(at, end - at);
  }
  // Consumes `word` if the letters at the cursor (after spaces) are exactly it.
  bool accept_word(std::string_view word) {
    skip_spaces();
    if (letters_at(pos_) != word) return false;
    pos_ += word.size();
    return true;
  }
  std::string describe_here() const {
    if (at_end()) return "the end of the line";
    const std::string word = letters_at(pos_);
    return fmt::format("'{}'", word.empty() ? std::string(1, peek()) : word);
  }
  void expect_end() {
    skip_spaces();
    if (at_end()) return;
    if (peek() == ']') fail_here("']' without '[' before it");
    fail_here(fmt::format("unexpected {} after the statement", describe_here()));
  }

  long parse_integer(const char* what) {
    skip_spaces();
    const std::size_t start = pos_;
    while (!at_end() && is_digit(peek())) ++pos_;
    if (pos_ == start || pos_ - start > 9)
      fail(static_cast<int>(start) + 1, fmt::format("expected {}", what));
    return std::stol(code_.substr(start, pos_ - start));
  }

  int add(Op op, int a, int b, int column) {
    Node n;
    n.op = op;
    n.a = a;
    n.b = b;
    n.column = column;
    nodes_.push_back(n);
    return static_cast<int>(nodes_.size()) - 1;
  }
  int add_number(double value, int column) {
    const int id = add(Op::kNumber, -1, -1, column);
    nodes_[id].number = value;
    return id;
  }

  // Expressions, loosest first: OR XOR < AND < EQ NE GT GE LT LE < + - < * / MOD < unary - < primary.
  int parse_expression() {
    int left = parse_and();
    for (;;) {
      skip_spaces();
      const int col = column();
      if (accept_word("OR"))
        left = add(Op::kOr, left, parse_and(), col);
      else if (accept_word("XOR"))
        left = add(Op::kXor, left, parse_and(), col);
      else
        return left;
    }
  }
  int parse_and() {
    int left = parse_comparison();
    for (;;) {
      skip_spaces();
      const int col = column();
      if (!accept_word("AND")) return left;
      left = add(Op::kAnd, left, parse_comparison(), col);
    }
  }
  int parse_comparison() {
    static constexpr std::pair<const char*, Op> kComparisons[] = {
        {"EQ", Op::kEq}, {"NE", Op::kNe}, {"GT", Op::kGt}, {"GE", Op::kGe}, {"LT", Op::kLt}, {"LE", Op::kLe}};
    const int left = parse_sum();
    skip_spaces();
    const int col = column();
    for (const auto& [word, op] : kComparisons)
      if (accept_word(word)) return add(op, left, parse_sum(), col);
    return left;
  }
  int parse_sum() {
    int left = parse_product();
    for (;;) {
      skip_spaces();
      const int col = column();
      if (peek() == '+' || peek() == '-') {
        const Op op = peek() == '+' ? Op::kAdd : Op::kSub;
        ++pos_;
        left = add(op, left, parse_product(), col);
      } else {
        return left;
      }
    }
  }
  int parse_product() {
    int left = parse_unary();
    for (;;) {
      skip_spaces();
      const int col = column();
      if (peek() == '*' || peek() == '/') {
        const Op op = peek() == '*' ? Op::kMul : Op::kDiv;
        ++pos_;
        left = add(op, left, parse_unary(), col);
      } else if (accept_word("MOD")) {
        left = add(Op::kMod, left, parse_unary(), col);
      } else {
        return left;
      }
    }
  }
  int parse_unary() {
    skip_spaces();
    const int col = column();
    if (peek() == '-') {
      ++pos_;
      return add(Op::kNeg, parse_unary(), -1, col);
    }
    if (peek() == '+') {
      ++pos_;
      return parse_unary();
    }
    return parse_primary();
  }
  int parse_primary() {
    skip_spaces();
    const char c = peek();
    if (is_digit(c) || c == '.') return parse_number();
    if (c == '#') return parse_variable();
    if (c == '[') return parse_bracket();
    if (is_letter(c)) return parse_function();
    fail_here(fmt::format("expected a number, a #variable, '[' or a function, found {}", describe_here()));
  }
  int parse_number() {
    const std::size_t start = pos_;
    bool point = false;
    while (!at_end() && (is_digit(peek()) || (peek() == '.' && !point))) {
      point = point || peek() == '.';
      ++pos_;
    }
    const std::string text = code_.substr(start, pos_ - start);
    double value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text == "." || ec != std::errc() || end != text.data() + text.size())
      fail(static_cast<int>(start) + 1, fmt::format("'{}' is not a number", text));
    return add_number(value, static_cast<int>(start) + 1);
  }
  int parse_variable() {
    const int col = column();
    ++pos_;  // '#'
    skip_spaces();
    int index = -1;
    if (is_digit(peek()))
      index = add_number(static_cast<double>(parse_integer("a variable number")), col);
    else if (peek() == '[')
      index = parse_bracket();
    else
      fail_here(fmt::format("expected a variable number or '[' after '#', found {}", describe_here()));
    return add(Op::kVariable, index, -1, col);
  }
  // `[ expression ]`
  int parse_bracket() {
    skip_spaces();
    const int open = column();
    if (peek() != '[') fail_here(fmt::format("expected '[', found {}", describe_here()));
    ++pos_;
    const int inside = parse_expression();
    skip_spaces();
    if (at_end()) fail(open, "'[' is not closed by ']' on this line");
    if (peek() != ']') fail_here(fmt::format("expected ']' or an operator, found {}", describe_here()));
    ++pos_;
    return inside;
  }
  int parse_function() {
    const int col = column();
    const std::string name = letters_at(pos_);
    const auto* found = std::find_if(std::begin(kFunctions), std::end(kFunctions),
                                     [&](const FunctionName& f) { return name == f.name; });
    if (found == std::end(kFunctions)) fail(col, fmt::format("unknown function or word '{}'", name));
    pos_ += name.size();
    skip_spaces();
    if (peek() != '[') fail_here(fmt::format("{} needs its argument in '[ ]'", name));
    const int open = column();
    ++pos_;
    const int a = parse_expression();
    skip_spaces();
    int b = -1;
    if (peek() == ',') {  // ATAN[y, x] and POW[x, y] of newer controls
      ++pos_;
      b = parse_expression();
      skip_spaces();
    }
    if (at_end()) fail(open, "'[' is not closed by ']' on this line");
    if (peek() != ']') fail_here(fmt::format("expected ']' or an operator, found {}", describe_here()));
    ++pos_;
    Function f = found->function;
    if (f == Function::kAtan && b < 0) {
      // ATAN[y]/[x]: the classic two-argument form (a division by a bracket right after ATAN[] is never
      // meant on a Fanuc control).
      const std::size_t save = pos_;
      skip_spaces();
      if (peek() == '/') {
        ++pos_;
        skip_spaces();
        if (peek() == '[')
          b = parse_bracket();
        else
          pos_ = save;
      } else {
        pos_ = save;
      }
    }
    if (f == Function::kAtan && b >= 0) f = Function::kAtan2;
    if (f == Function::kPow && b < 0) fail(col, "POW needs two arguments: POW[x, y]");
    if (f != Function::kAtan2 && f != Function::kPow && b >= 0)
      fail(col, fmt::format("{} takes one argument", name));
    const int id = add(Op::kFunction, a, b, col);
    nodes_[id].function = f;
    return id;
  }

  // An address's value: a number, `#var`, `[expr]`, each with an optional sign.
  int parse_address_value(char letter) {
    skip_spaces();
    const int col = column();
    bool negative = false;
    if (peek() == '-' || peek() == '+') {
      negative = peek() == '-';
      ++pos_;
      skip_spaces();
    }
    int value = -1;
    const char c = peek();
    if (is_digit(c) || c == '.')
      value = parse_number();
    else if (c == '#')
      value = parse_variable();
    else if (c == '[')
      value = parse_bracket();
    else if (is_letter(c))
      fail_here(
          fmt::format("address {} needs a number, #variable or [expression]; write functions in brackets "
                      "({}[{}[...]])",
                      letter, letter, letters_at(pos_)));
    else
      fail_here(fmt::format("address {} needs a value, found {}", letter, describe_here()));
    return negative ? add(Op::kNeg, value, -1, col) : value;
  }

  void parse_assignment_into(Line& l) {
    skip_spaces();
    l.target_column = column();
    if (peek() != '#') fail_here(fmt::format("expected '#variable =', found {}", describe_here()));
    const int variable = parse_variable();
    l.target = nodes_[variable].a;
    skip_spaces();
    if (peek() != '=') fail_here(fmt::format("expected '=' after the variable, found {}", describe_here()));
    ++pos_;
    l.value = parse_expression();
  }
  int parse_loop_id() {
    skip_spaces();
    const int col = column();
    const long m = parse_integer("a loop number (1, 2 or 3)");
    if (m < 1 || m > 3) fail(col, fmt::format("loop number must be 1, 2 or 3, got {}", m));
    return static_cast<int>(m);
  }

  void parse_keyword(const std::string& word, Line& l) {
    pos_ += word.size();
    if (word == "IF") {
      l.condition = parse_bracket();
      skip_spaces();
      if (accept_word("GOTO")) {
        l.kind = Kind::kIfGoto;
        l.value = parse_expression();
      } else if (accept_word("THEN")) {
        l.kind = Kind::kIfThen;
        parse_assignment_into(l);
      } else {
        fail_here(fmt::format("expected GOTO or THEN after IF [...], found {}", describe_here()));
      }
    } else if (word == "WHILE") {
      l.kind = Kind::kWhile;
      l.condition = parse_bracket();
      skip_spaces();
      if (!accept_word("DO"))
        fail_here(fmt::format("expected DO after WHILE [...], found {}", describe_here()));
      l.loop_id = parse_loop_id();
    } else if (word == "DO") {
      l.kind = Kind::kWhile;
      l.loop_id = parse_loop_id();
    } else if (word == "END") {
      l.kind = Kind::kEnd;
      l.loop_id = parse_loop_id();
    } else if (word == "GOTO") {
      l.kind = Kind::kGoto;
      l.value = parse_expression();
    } else {
      fail(l.column, fmt::format("unknown word '{}'", word));
    }
  }

  void parse_words(Line& l) {
    for (skip_spaces(); !at_end(); skip_spaces()) {
      const char c = peek();
      const int col = column();
      if (!is_letter(c)) fail_here(fmt::format("expected an address letter, found '{}'", c));
      if (const std::string word = letters_at(pos_); word.size() > 1)
        fail_here(fmt::format("unknown word '{}'", word));
      if (c == 'N' || c == 'O')
        fail_here(
            fmt::format("{} must start the block", c == 'N' ? "a sequence number N" : "a program number O"));
      ++pos_;
      l.words.push_back({c, col, parse_address_value(c)});
    }
  }

  int line_number_;
  const std::string& file_;
  std::vector<Node>& nodes_;
  std::string code_;
  std::vector<std::string> comments_;
  std::size_t pos_ = 0;
};

std::vector<std::string_view> split_lines(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    auto end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view l = text.substr(start, end - start);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    lines.push_back(l);
    start = end + 1;
  }
  return lines;
}

std::string program_name(long number) {
  return number < 0 ? "the main program" : fmt::format("O{}", number);
}

// Matches WHILE/DO with END inside one program and fills Line::partner.
class LoopMatcher {
 public:
  explicit LoopMatcher(const std::string& file) : file_(file) {}

  void add(std::vector<Line>& lines, int index) {
    Line& l = lines[index];
    if (l.kind == Kind::kWhile) {
      for (const int open : open_)
        if (lines[open].loop_id == l.loop_id)
          throw InputError(
              {file_, l.line, l.column}, {},
              fmt::format("DO {} is already open (line {}): loops nested in one another need different "
                          "numbers",
                          l.loop_id, lines[open].line));
      open_.push_back(index);
    } else if (l.kind == Kind::kEnd) {
      const auto it = std::find_if(open_.begin(), open_.end(),
                                   [&](int open) { return lines[open].loop_id == l.loop_id; });
      if (it == open_.end())
        throw InputError({file_, l.line, l.column}, {},
                         fmt::format("END {} without a DO {} before it", l.loop_id, l.loop_id));
      if (it + 1 != open_.end())
        throw InputError(
            {file_, l.line, l.column}, {},
            fmt::format("END {} closes the loop of line {} while DO {} (line {}) inside it is still "
                        "open: loops must nest",
                        l.loop_id, lines[*it].line, lines[open_.back()].loop_id, lines[open_.back()].line));
      l.partner = *it;
      lines[*it].partner = index;
      open_.pop_back();
    }
  }

  // Throws for a loop still open at the end of the program, then starts afresh for the next one.
  void close(const std::vector<Line>& lines, long program_number) {
    if (open_.empty()) return;
    const Line& l = lines[open_.back()];
    throw InputError(
        {file_, l.line, l.column}, {},
        fmt::format("DO {} has no END {} in {}", l.loop_id, l.loop_id, program_name(program_number)));
  }

 private:
  const std::string& file_;
  std::vector<int> open_;
};

bool holds_code(const std::vector<Line>& lines, const Program& p) {
  for (int i = p.first; i < p.last; ++i)
    if (lines[i].kind != Kind::kEmpty || lines[i].label) return true;
  return false;
}

}  // namespace

const char* function_name(Function f) {
  if (f == Function::kAtan2) return "ATAN";
  for (const auto& [name, function] : kFunctions)
    if (function == f) return name;
  return "?";
}

Parsed parse_macro_program(std::string_view text, const std::string& file_name) {
  Parsed p;
  p.file = file_name;
  std::vector<Program> programs(1);
  LoopMatcher loops(p.file);
  const auto close_program = [&](int end) {
    programs.back().last = end;
    loops.close(p.lines, programs.back().number);
  };
  const std::vector<std::string_view> raw = split_lines(text);
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const int index = static_cast<int>(p.lines.size());
    p.lines.push_back(LineParser(raw[i], static_cast<int>(i) + 1, p.file, p.nodes).parse());
    const Line& l = p.lines.back();
    if (l.kind == Kind::kProgram) {
      close_program(index);
      for (const Program& other : programs)
        if (other.number == l.program_number)
          throw InputError(
              {p.file, l.line, l.column}, {},
              fmt::format("program O{} is already defined at line {}", l.program_number, other.o_line));
      programs.push_back({l.program_number, l.line, index + 1, index + 1, {}});
      continue;
    }
    if (l.label) programs.back().labels[*l.label].push_back(index);
    loops.add(p.lines, index);
  }
  close_program(static_cast<int>(p.lines.size()));
  // Code before the first O line is the main program; without any, the first O program is.
  if (programs.size() > 1 && !holds_code(p.lines, programs.front())) programs.erase(programs.begin());
  p.programs = std::move(programs);
  return p;
}

}  // namespace beadtwin::gcode::macro
