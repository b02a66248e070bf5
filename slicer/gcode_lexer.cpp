#include "slicer/gcode_lexer.hpp"

#include <array>
#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace beadtwin::slicer {
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
  std::string up;
  for (const char c : run) up += upper(c);
  for (const std::string_view k : kKeywords)
    if (up == k) return true;
  return false;
}

class Lexer {
 public:
  Lexer(std::string_view text, int line, const std::string& file) : text_(text), line_(line), file_(file) {
    while (!text_.empty() && (text_.back() == '\r' || text_.back() == '\n')) text_.remove_suffix(1);
  }

  LexedLine run() {
    LexedLine out;
    out.block.line = line_;
    if (has_macro_syntax(text_)) {
      out.kind = LineKind::kMacro;
      return out;
    }
    std::size_t i = 0;
    while (i < text_.size() && is_space(text_[i])) ++i;
    if (i < text_.size() && text_[i] == '%') return out;
    if (i < text_.size() && text_[i] == '/') {
      out.block.block_delete = true;
      ++i;
    }
    while (i < text_.size()) {
      const char c = text_[i];
      if (is_space(c)) {
        ++i;
      } else if (c == ';') {
        out.block.comments.push_back(trimmed(text_.substr(i + 1)));
        break;
      } else if (c == '(') {
        i = comment(i, ')', out.block);
      } else if (c == '"') {
        i = comment(i, '"', out.block);
      } else if (c == '*') {
        ++i;  // checksum: the number after it is dropped too
        while (i < text_.size() && is_digit(text_[i])) ++i;
      } else if (is_alpha(c)) {
        if (i + 1 < text_.size() && is_alpha(text_[i + 1])) {
          std::size_t end = i;
          while (end < text_.size() && is_alpha(text_[end])) ++end;
          if (is_macro_keyword(text_.substr(i, end - i))) {
            out.kind = LineKind::kMacro;
            out.block = Block{};
            out.block.line = line_;
            return out;
          }
        }
        const std::size_t words_before = out.block.words.size();
        i = word(i, out.block);
        const bool message = out.block.words.size() > words_before && out.block.words.back().letter == 'M' &&
                             (out.block.words.back().value == 117.0 || out.block.words.back().value == 118.0);
        if (message) {
          // Display and host messages: free text to the end of the line.
          const std::string msg = trimmed(text_.substr(i));
          if (!msg.empty()) out.block.comments.push_back(msg);
          break;
        }
      } else {
        fail(i, fmt::format("unexpected {} in a G-code line", shown(c)));
      }
    }
    return out;
  }

 private:
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
    std::size_t digits = 0;
    while (i < text_.size() && is_digit(text_[i])) ++i, ++digits;
    if (i < text_.size() && text_[i] == '.') {
      ++i;
      while (i < text_.size() && is_digit(text_[i])) ++i, ++digits;
    }
    if (digits == 0) {
      const std::string found =
          start < text_.size() ? shown(text_[start]) : std::string("the end of the line");
      fail(start, fmt::format("expected a number after '{}', found {}", letter, found));
    }
    double value = 0.0;
    const auto [ptr, ec] = std::from_chars(text_.data() + digits_at, text_.data() + i, value);
    if (ec != std::errc() || ptr != text_.data() + i || !std::isfinite(value))
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
  return Lexer(text, line, file_name).run();
}

}  // namespace beadtwin::slicer
