#include "gcode/macro.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "gcode/macro_parse.hpp"

namespace beadtwin::gcode {

namespace {

using macro::Function;
using macro::Kind;
using macro::Line;
using macro::Node;
using macro::Op;
using macro::Parsed;

using Value = std::optional<double>;  // nullopt: vacant

constexpr int kVariableCount = 1000;
constexpr long kAlarmVariable = 3000;
constexpr std::size_t kMaxCallDepth = 10;
constexpr double kDegree = std::numbers::pi / 180.0;

bool is_variable(long i) {
  return (i >= 1 && i <= 33) || (i >= 100 && i <= 199) || (i >= 500 && i <= 999);
}

// Sine of an angle in degrees, reduced to ±45° about a multiple of 90° first so that it is exactly 0 or ±1
// there, and exactly ±1/2 at ±30° from one; -0 comes out as 0.
double sin_deg(double deg) {
  double r = std::fmod(deg, 360.0);
  if (r < 0) r += 360.0;
  const double quadrant = std::round(r / 90.0);
  const double d = r - 90.0 * quadrant;
  const double s = d == 30.0 ? 0.5 : d == -30.0 ? -0.5 : std::sin(d * kDegree);
  const double c = std::cos(d * kDegree);
  switch (static_cast<int>(quadrant) % 4) {
    case 0:
      return s + 0.0;
    case 1:
      return c + 0.0;
    case 2:
      return -s + 0.0;
    default:
      return -c + 0.0;
  }
}
double cos_deg(double deg) {
  return sin_deg(deg + 90.0);
}

// a EQ b with a relative tolerance, so that a loop counter stepped by 0.1 meets its end value.
bool nearly_equal(double a, double b) {
  return std::abs(a - b) <= 1e-9 * std::max({1.0, std::abs(a), std::abs(b)});
}

std::string number_text(double v) {
  return fmt::format("{:g}", v);
}

std::string program_name(long number) {
  return number < 0 ? "the main program" : fmt::format("O{}", number);
}

// The loop a run was going round, for the message when it runs out of steps.
struct BackJump {
  int line = 0;
  std::string what;
};

class Interpreter {
 public:
  Interpreter(const Parsed& parsed, const MacroOptions& options,
              const std::function<void(const Block&)>& emit)
      : p_(parsed), options_(options), emit_(emit), variables_(kVariableCount) {
    for (std::size_t i = 0; i < p_.programs.size(); ++i) program_index_[p_.programs[i].number] = i;
  }

  void run() {
    program_ = 0;
    pc_ = p_.programs[0].first;
    while (!finished_) {
      if (pc_ >= p_.programs[program_].last) {
        end_of_program();
        continue;
      }
      line_ = &p_.lines[pc_];
      count_step();
      if (line_->block_delete && options_.block_delete) {
        ++pc_;
        continue;
      }
      execute(*line_);
    }
  }

 private:
  struct Frame {
    std::size_t program = 0;  // the caller
    int return_pc = 0;        // the caller's line after the M98
    long repeats_left = 0;    // further runs of the subprogram (L - 1 at the call)
    int call_line = 0;
  };

  [[noreturn]] void fail(int column, const std::string& message) const {
    throw InputError({p_.file, line_->line, column}, {}, message);
  }
  [[noreturn]] void fail_at(int node, const std::string& message) const {
    fail(p_.nodes[node].column, message);
  }

  void count_step() {
    if (++steps_ <= options_.max_steps) return;
    const int line = back_jump_.line > 0 ? back_jump_.line : line_->line;
    const std::string what =
        back_jump_.line > 0 ? back_jump_.what : fmt::format("last at line {}", line_->line);
    throw InputError({p_.file, line, 0}, {},
                     fmt::format("program did not finish after {} steps ({}); if it is meant to run this "
                                 "long, raise the machine's gcode.macro_step_limit",
                                 options_.max_steps, what));
  }

  // ---- expressions

  Value eval(int id) const {
    const Node& n = p_.nodes[id];
    switch (n.op) {
      case Op::kNumber:
        return n.number;
      case Op::kVariable:
        return read_variable(n);
      case Op::kNeg: {
        const Value v = eval(n.a);
        return v ? Value(-*v + 0.0) : std::nullopt;
      }
      case Op::kEq:
      case Op::kNe: {
        const Value a = eval(n.a);
        const Value b = eval(n.b);
        const bool equal = (!a || !b) ? (!a && !b) : nearly_equal(*a, *b);
        return (equal == (n.op == Op::kEq)) ? 1.0 : 0.0;
      }
      case Op::kFunction:
        return function(n);
      default:
        return arithmetic(n);
    }
  }
  double number(int id) const { return eval(id).value_or(0.0); }
  bool truth(int id) const { return number(id) != 0.0; }

  // A value that must be a whole number: a variable's index, a label, a program number, a count.
  long whole(int id, const char* what) const {
    const double v = number(id);
    const double r = std::round(v);
    if (std::abs(v - r) > 1e-9 || std::abs(r) > 1e15)
      fail_at(id, fmt::format("{} must be a whole number, got {}", what, number_text(v)));
    return static_cast<long>(r);
  }

  Value read_variable(const Node& n) const {
    const long i = whole(n.a, "a variable number");
    if (i == 0) return std::nullopt;
    if (!is_variable(i)) fail(n.column, unknown_variable(i));
    return variables_[i];
  }
  static std::string unknown_variable(long i) {
    return fmt::format("#{} is not a variable here: locals are #1-#33, commons #100-#199 and #500-#999", i);
  }

  double arithmetic(const Node& n) const {
    const double a = number(n.a);
    const double b = number(n.b);
    switch (n.op) {
      case Op::kAdd:
        return checked(n, a + b);
      case Op::kSub:
        return checked(n, a - b);
      case Op::kMul:
        return checked(n, a * b);
      case Op::kDiv:
        if (b == 0) fail(n.column, fmt::format("division by zero ({} / 0)", number_text(a)));
        return checked(n, a / b);
      case Op::kMod:
        if (b == 0) fail(n.column, fmt::format("{} MOD 0 divides by zero", number_text(a)));
        return std::fmod(a, b);
      case Op::kGt:
        return a > b && !nearly_equal(a, b) ? 1.0 : 0.0;
      case Op::kGe:
        return a > b || nearly_equal(a, b) ? 1.0 : 0.0;
      case Op::kLt:
        return a < b && !nearly_equal(a, b) ? 1.0 : 0.0;
      case Op::kLe:
        return a < b || nearly_equal(a, b) ? 1.0 : 0.0;
      case Op::kAnd:
        return static_cast<double>(bits(n, n.a, a) & bits(n, n.b, b));
      case Op::kOr:
        return static_cast<double>(bits(n, n.a, a) | bits(n, n.b, b));
      case Op::kXor:
        return static_cast<double>(bits(n, n.a, a) ^ bits(n, n.b, b));
      default:
        throw InternalError("macro: arithmetic on a node that is not an operator");
    }
  }
  std::int64_t bits(const Node& n, int operand, double v) const {
    const double r = std::round(v);
    const char* name = n.op == Op::kAnd ? "AND" : n.op == Op::kOr ? "OR" : "XOR";
    if (std::abs(v - r) > 1e-9 || std::abs(r) > 9e15)
      fail_at(operand, fmt::format("{} works on whole numbers, got {}", name, number_text(v)));
    return static_cast<std::int64_t>(r);
  }
  double checked(const Node& n, double v) const {
    if (!std::isfinite(v)) fail(n.column, "the result is too large to be a number");
    return v;
  }

  double function(const Node& n) const {
    const double x = number(n.a);
    const char* name = macro::function_name(n.function);
    const auto out_of_range = [&](const char* range) {
      fail(n.column, fmt::format("{}[{}]: the argument must be {}", name, number_text(x), range));
    };
    switch (n.function) {
      case Function::kSin:
        return sin_deg(x);
      case Function::kCos:
        return cos_deg(x);
      case Function::kTan: {
        const double c = cos_deg(x);
        if (c == 0) fail(n.column, fmt::format("TAN[{}] is infinite", number_text(x)));
        return sin_deg(x) / c;
      }
      case Function::kAsin:
        if (std::abs(x) > 1) out_of_range("between -1 and 1");
        return std::asin(x) / kDegree;
      case Function::kAcos:
        if (std::abs(x) > 1) out_of_range("between -1 and 1");
        return std::acos(x) / kDegree;
      case Function::kAtan:
        return std::atan(x) / kDegree;
      case Function::kAtan2: {
        const double y = x;
        const double along = number(n.b);
        if (y == 0 && along == 0) fail(n.column, "ATAN[0]/[0] has no angle");
        const double deg = std::atan2(y, along) / kDegree;
        return deg < 0 ? deg + 360.0 : deg + 0.0;
      }
      case Function::kSqrt:
        if (x < 0) out_of_range("0 or more");
        return std::sqrt(x);
      case Function::kAbs:
        return std::abs(x);
      case Function::kRound:
        return std::round(x) + 0.0;
      case Function::kFix:
        return std::trunc(x) + 0.0;
      case Function::kFup:
        return (x < 0 ? std::floor(x) : std::ceil(x)) + 0.0;
      case Function::kLn:
        if (x <= 0) out_of_range("more than 0");
        return std::log(x);
      case Function::kExp:
        return checked(n, std::exp(x));
      case Function::kPow: {
        const double v = std::pow(x, number(n.b));
        if (std::isnan(v))
          fail(n.column,
               fmt::format("POW[{}, {}] is not a real number", number_text(x), number_text(number(n.b))));
        return checked(n, v);
      }
    }
    throw InternalError("macro: unknown function");
  }

  // ---- statements

  void execute(const Line& l) {
    switch (l.kind) {
      case Kind::kEmpty:
      case Kind::kProgram:
        if (!l.comments.empty()) emit_block(Block{l.line, {}, l.comments, l.block_delete});
        ++pc_;
        return;
      case Kind::kAssign:
        assign(l);
        ++pc_;
        return;
      case Kind::kIfGoto:
        if (truth(l.condition))
          go_to(l.value);
        else
          ++pc_;
        return;
      case Kind::kIfThen:
        if (truth(l.condition)) assign(l);
        ++pc_;
        return;
      case Kind::kGoto:
        go_to(l.value);
        return;
      case Kind::kWhile:
        pc_ = (l.condition < 0 || truth(l.condition)) ? pc_ + 1 : l.partner + 1;
        return;
      case Kind::kEnd: {
        const Line& start = p_.lines[l.partner];
        back_jump_ = {start.line, start.condition < 0
                                      ? fmt::format("DO {} at line {} still looping", l.loop_id, start.line)
                                      : fmt::format("WHILE at line {} still looping", start.line)};
        pc_ = l.partner;
        return;
      }
      case Kind::kWords:
        words(l);
        return;
    }
  }

  void assign(const Line& l) {
    const long i = whole(l.target, "a variable number");
    if (i == kAlarmVariable) {
      const std::string text = l.comments.empty() ? std::string() : ": " + l.comments.front();
      fail(l.target_column,
           fmt::format("the program raised alarm #3000 = {}{}", number_text(number(l.value)), text));
    }
    if (i == 0) fail(l.target_column, "#0 is always vacant and cannot be assigned");
    if (!is_variable(i)) fail(l.target_column, unknown_variable(i));
    variables_[i] = eval(l.value);
  }

  // The line labelled N`label` in `program`.
  int find_label(std::size_t program, long label, int column, const char* what) const {
    const macro::Program& prog = p_.programs[program];
    const auto it = prog.labels.find(label);
    if (it == prog.labels.end())
      fail(column,
           fmt::format("{} {}: there is no N{} in {}", what, label, label, program_name(prog.number)));
    if (it->second.size() > 1)
      fail(column, fmt::format("{} {}: N{} labels lines {} and {} of {}", what, label, label,
                               p_.lines[it->second[0]].line, p_.lines[it->second[1]].line,
                               program_name(prog.number)));
    return it->second.front();
  }

  void go_to(int target_node) {
    const long label = whole(target_node, "the GOTO target");
    const int target = find_label(program_, label, p_.nodes[target_node].column, "GOTO");
    if (target <= pc_)
      back_jump_ = {line_->line, fmt::format("GOTO at line {} still jumping back to line {}", line_->line,
                                             p_.lines[target].line)};
    pc_ = target;
  }

  // A line of address words: evaluated, emitted, then M98/M99/M02/M30 acted on.
  void words(const Line& l) {
    Block block{l.line, {}, l.comments, l.block_delete};
    for (const macro::AddressWord& w : l.words)
      if (const Value v = eval(w.value)) block.words.push_back({w.letter, *v, w.column});
    const auto m_code = [&](double code) {
      return std::find_if(block.words.begin(), block.words.end(),
                          [&](const Word& w) { return w.letter == 'M' && w.value == code; });
    };
    const bool end = m_code(2) != block.words.end() || m_code(30) != block.words.end();
    const auto call = m_code(98);
    const auto ret = m_code(99);
    if (call != block.words.end() && ret != block.words.end()) fail(ret->column, "M98 and M99 in one block");
    std::optional<Word> p_word, l_word;
    if (!end && (call != block.words.end() || ret != block.words.end())) {
      // The P (and for M98 the L) of the block belong to the call or return, not to the machine.
      const bool is_call = call != block.words.end();
      const int column = is_call ? call->column : ret->column;
      std::erase_if(block.words,
                    [](const Word& w) { return w.letter == 'M' && (w.value == 98 || w.value == 99); });
      for (auto it = block.words.begin(); it != block.words.end();) {
        if (it->letter == 'P' || (is_call && it->letter == 'L')) {
          (it->letter == 'P' ? p_word : l_word) = *it;
          it = block.words.erase(it);
        } else {
          ++it;
        }
      }
      emit_block(block);
      if (is_call)
        call_subprogram(column, p_word, l_word);
      else
        return_from_subprogram(p_word);
      return;
    }
    emit_block(block);
    if (end)
      finished_ = true;
    else
      ++pc_;
  }

  void emit_block(const Block& block) const {
    if (!block.words.empty() || !block.comments.empty()) emit_(block);
  }

  static long whole_word(const Word& w, const Line& l, const std::string& file) {
    const double r = std::round(w.value);
    if (std::abs(w.value - r) > 1e-9 || r < 0 || r > 1e9)
      throw InputError(
          {file, l.line, w.column}, {},
          fmt::format("{} must be a whole number 0 or more, got {}", w.letter, number_text(w.value)));
    return static_cast<long>(r);
  }

  void call_subprogram(int column, const std::optional<Word>& p, const std::optional<Word>& l) {
    if (!p) fail(column, "M98 needs P<program number>");
    const long number = whole_word(*p, *line_, p_.file);
    const long count = l ? whole_word(*l, *line_, p_.file) : 1;
    const auto it = program_index_.find(number);
    if (it == program_index_.end())
      fail(p->column, fmt::format("M98 P{}: the file has no program O{}", number, number));
    if (count == 0) {
      ++pc_;
      return;
    }
    if (stack_.size() >= kMaxCallDepth)
      fail(column, fmt::format("M98 P{}: subprogram calls nested more than {} deep (does O{} call itself?)",
                               number, kMaxCallDepth, number));
    stack_.push_back({program_, pc_ + 1, count - 1, line_->line});
    program_ = it->second;
    pc_ = p_.programs[program_].first;
  }

  void return_from_subprogram(const std::optional<Word>& p) {
    if (stack_.empty()) {  // M99 in the main program: a control would start it again; a run ends
      finished_ = true;
      return;
    }
    Frame& frame = stack_.back();
    if (frame.repeats_left > 0) {
      --frame.repeats_left;
      pc_ = p_.programs[program_].first;
      return;
    }
    const Frame caller = frame;
    stack_.pop_back();
    program_ = caller.program;
    if (!p) {
      pc_ = caller.return_pc;
      return;
    }
    const int target = find_label(program_, whole_word(*p, *line_, p_.file), p->column, "M99 P");
    if (target < caller.return_pc)
      back_jump_ = {line_->line, fmt::format("M99 at line {} still returning to line {}", line_->line,
                                             p_.lines[target].line)};
    pc_ = target;
  }

  void end_of_program() {
    if (stack_.empty()) {
      finished_ = true;
      return;
    }
    const macro::Program& prog = p_.programs[program_];
    throw InputError({p_.file, prog.o_line, 0}, {},
                     fmt::format("{} (called at line {}) ends without M99", program_name(prog.number),
                                 stack_.back().call_line));
  }

  const Parsed& p_;
  const MacroOptions& options_;
  const std::function<void(const Block&)>& emit_;
  std::vector<Value> variables_;
  std::map<long, std::size_t> program_index_;
  std::vector<Frame> stack_;
  std::size_t program_ = 0;
  int pc_ = 0;
  const Line* line_ = nullptr;
  long steps_ = 0;
  bool finished_ = false;
  BackJump back_jump_;
};

}  // namespace

MacroProgram::MacroProgram(std::string_view text, MacroOptions options)
    : parsed_(std::make_unique<const macro::Parsed>(macro::parse_macro_program(text, options.file_name))),
      options_(std::move(options)) {}

MacroProgram::~MacroProgram() = default;
MacroProgram::MacroProgram(MacroProgram&&) noexcept = default;
MacroProgram& MacroProgram::operator=(MacroProgram&&) noexcept = default;

void MacroProgram::run(const std::function<void(const Block&)>& emit) const {
  Interpreter(*parsed_, options_, emit).run();
}

}  // namespace beadtwin::gcode
