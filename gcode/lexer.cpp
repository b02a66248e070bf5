#include "gcode/lexer.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "core/error.hpp"

namespace beadtwin::gcode {
namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}
bool is_digit(char c) {
  return c >= '0' && c <= '9';
}
bool is_alpha(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}
char upper(char c) {
  return c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c;
}

std::string trimmed(std::string_view s) {
  std::size_t a = 0;
  std::size_t b = s.size();
  while (a < b && is_space(s[a])) ++a;
  while (b > a && is_space(s[b - 1])) --b;
  return std::string(s.substr(a, b - a));
}

// How a character is shown in a message: printable ones quoted, others by code.
std::string shown(char c) {
  const auto u = static_cast<unsigned char>(c);
  if (u >= 0x20 && u < 0x7f) return fmt::format("'{}'", c);
  return fmt::format("byte 0x{:02x}", u);
}

// `#` or `[` outside comments: variables or expressions, which only the macro interpreter evaluates.
bool has_macro_syntax(std::string_view text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == ';') return false;
    if (c == '(') {
      const std::size_t close = text.find(')', i + 1);
      if (close == std::string_view::npos) return false;
      i = close;
      continue;
    }
    if (c == '"') {
      const std::size_t close = text.find('"', i + 1);
      if (close == std::string_view::npos) return false;
      i = close;
      continue;
    }
    if (c == '#' || c == '[') return true;
  }
  return false;
}

// A run of letters that starts a macro statement (Fanuc custom macro B): IF, WHILE, GOTO, DO, END.
bool is_macro_keyword(std::string_view run) {
  static constexpr std::array<std::string_view, 5> kKeywords = {"IF", "WHILE", "GOTO", "DO", "END"};
  for (const std::string_view k : kKeywords) {
    if (k.size() != run.size()) continue;
    bool same = true;
    for (std::size_t i = 0; i < k.size() && same; ++i) same = upper(run[i]) == k[i];
    if (same) return true;
  }
  return false;
}

// The number with `digits` digits, `decimals` of them after the point, that are `mantissa` as an integer
// (modulo 2^64), and that std::from_chars reads from [first, last). Most numbers in a program have few
// digits: their integer and the power of ten they are scaled by are then exact doubles, and one division
// rounds the quotient correctly, as from_chars does. The rest go to from_chars. False when from_chars does
// not read the whole range or overflows.
bool read_number(std::uint64_t mantissa, std::size_t digits, std::size_t decimals, const char* first,
                 const char* last, double& value) {
  static constexpr std::array<double, 20> kPow10 = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,
                                                    1e7,  1e8,  1e9,  1e10, 1e11, 1e12, 1e13,
                                                    1e14, 1e15, 1e16, 1e17, 1e18, 1e19};
  if (digits <= 19 && mantissa <= (std::uint64_t{1} << 53)) {
    value = static_cast<double>(mantissa) / kPow10[decimals];
    return true;
  }
  const auto [ptr, ec] = std::from_chars(first, last, value);
  return ec == std::errc() && ptr == last && std::isfinite(value);
}

class Lexer {
 public:
  Lexer(std::string_view text, int line, const std::string& file) : text_(text), line_(line), file_(file) {
    while (!text_.empty() && (text_.back() == '\r' || text_.back() == '\n')) text_.remove_suffix(1);
  }

  // A line with macro syntax is the macro interpreter's, whatever else it holds. The lexer finds `#` and
  // `[` where has_macro_syntax does (outside comments and strings), and no plain line holds them: the
  // line is searched for them only where lexing stops early (a tape marker, a message) or fails.
  LineKind run(Block& out) {
    out.line = line_;
    try {
      if (lex(out) == LineKind::kPlain) return LineKind::kPlain;
    } catch (const InputError&) {
      if (!has_macro_syntax(text_)) throw;
    }
    out.words.clear();
    out.comments.clear();
    out.block_delete = false;
    return LineKind::kMacro;
  }

 private:
  LineKind lex(Block& out) {
    out.words.clear();
    out.comments.clear();
    out.block_delete = false;
    std::size_t i = 0;
    while (i < text_.size() && is_space(text_[i])) ++i;
    if (i < text_.size() && text_[i] == '%')
      return has_macro_syntax(text_) ? LineKind::kMacro : LineKind::kPlain;
    if (i < text_.size() && text_[i] == '/') {
      out.block_delete = true;
      ++i;
    }
    while (i < text_.size()) {
      const char c = text_[i];
      if (is_space(c)) {
        ++i;
      } else if (c == ';') {
        out.comments.push_back(trimmed(text_.substr(i + 1)));
        break;
      } else if (c == '(') {
        i = comment(i, ')', out);
      } else if (c == '"') {
        i = comment(i, '"', out);
      } else if (c == '*') {
        ++i;  // checksum: the number after it is dropped too
        while (i < text_.size() && is_digit(text_[i])) ++i;
      } else if (is_alpha(c)) {
        if (i + 1 < text_.size() && is_alpha(text_[i + 1])) {
          std::size_t end = i;
          while (end < text_.size() && is_alpha(text_[end])) ++end;
          if (is_macro_keyword(text_.substr(i, end - i))) return LineKind::kMacro;
        }
        const std::size_t words_before = out.words.size();
        i = word(i, out);
        const bool message = out.words.size() > words_before && out.words.back().letter == 'M' &&
                             (out.words.back().value == 117.0 || out.words.back().value == 118.0);
        if (message) {
          // Display and host messages: free text to the end of the line.
          if (has_macro_syntax(text_)) return LineKind::kMacro;
          std::string msg = trimmed(text_.substr(i));
          if (!msg.empty()) out.comments.push_back(std::move(msg));
          break;
        }
      } else {
        fail(i, fmt::format("unexpected {} in a G-code line", shown(c)));
      }
    }
    return LineKind::kPlain;
  }

  [[noreturn]] void fail(std::size_t pos, const std::string& message) const {
    throw InputError(SourceLocation{file_, line_, static_cast<int>(pos) + 1}, "gcode", message);
  }

  // A comment opened at `open_at`; returns the position after it. An unclosed one runs to the end.
  std::size_t comment(std::size_t open_at, char close, Block& block) const {
    const std::size_t end = text_.find(close, open_at + 1);
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    block.comments.push_back(trimmed(text_.substr(open_at + 1, stop - open_at - 1)));
    return end == std::string_view::npos ? text_.size() : end + 1;
  }

  // A word whose letter is at `at`; returns the position after its number. N words are dropped, and so is
  // the letter of a string parameter (M862.3 P "MK3S").
  std::size_t word(std::size_t at, Block& block) const {
    const char letter = upper(text_[at]);
    std::size_t i = at + 1;
    while (i < text_.size() && is_space(text_[i])) ++i;
    const std::size_t start = i;
    if (start < text_.size() && text_[start] == '"') return start;  // a string parameter: kept as a comment
    bool negative = false;
    if (i < text_.size() && (text_[i] == '+' || text_[i] == '-')) {
      negative = text_[i] == '-';
      ++i;
    }
    const std::size_t digits_at = i;
    std::size_t digits = 0, decimals = 0;
    std::uint64_t mantissa = 0;  // the digits as an integer (modulo 2^64)
    for (; i < text_.size() && is_digit(text_[i]); ++i, ++digits)
      mantissa = mantissa * 10 + static_cast<std::uint64_t>(text_[i] - '0');
    if (i < text_.size() && text_[i] == '.') {
      for (++i; i < text_.size() && is_digit(text_[i]); ++i, ++decimals)
        mantissa = mantissa * 10 + static_cast<std::uint64_t>(text_[i] - '0');
      digits += decimals;
    }
    if (digits == 0) {
      const std::string found =
          start < text_.size() ? shown(text_[start]) : std::string("the end of the line");
      fail(start, fmt::format("expected a number after '{}', found {}", letter, found));
    }
    double value = 0.0;
    if (!read_number(mantissa, digits, decimals, text_.data() + digits_at, text_.data() + i, value))
      fail(start, fmt::format("malformed number '{}' after '{}'", text_.substr(start, i - start), letter));
    if (letter != 'N')
      block.words.push_back(Word{letter, negative ? -value : value, static_cast<int>(at) + 1});
    return i;
  }

  std::string_view text_;
  int line_;
  const std::string& file_;
};

}  // namespace

LexedLine lex_gcode_line(std::string_view text, int line, const std::string& file_name) {
  LexedLine out;
  out.kind = Lexer(text, line, file_name).run(out.block);
  return out;
}

LineKind lex_gcode_line(std::string_view text, int line, const std::string& file_name, Block& block) {
  return Lexer(text, line, file_name).run(block);
}

}  // namespace beadtwin::gcode
