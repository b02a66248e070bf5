#include "gcode/program_reader.hpp"

#include <algorithm>
#include <cstring>
#include <istream>
#include <iterator>
#include <optional>
#include <string_view>

#include <fmt/format.h>

#include "core/error.hpp"
#include "gcode/lexer.hpp"
#include "gcode/macro.hpp"

namespace beadtwin::gcode {
namespace {

constexpr std::size_t kChunk = std::size_t{1} << 16;
constexpr std::streamoff kBytesPerMove = 20;  // room is made for a move per 20 bytes: see read_gcode
constexpr std::size_t kMaxLine = std::size_t{1} << 20;  // 1 MB: no G-code line is that long
// Macro programs are run whole by the interpreter: the text is kept while it is no longer than this, so a
// macro line found within it can start the program over; beyond it the program is plain G-code, streamed.
constexpr std::size_t kMacroText = std::size_t{8} << 20;

// A parameterised (Fanuc macro) program, run by the macro interpreter into the reader.
Toolpath read_macro(const std::string& text, const std::string& file_name, const ReaderOptions& options,
                    ReadStats* stats) {
  MacroOptions mo;
  mo.file_name = file_name;
  mo.block_delete = options.block_delete;
  mo.max_steps = options.max_macro_steps;
  const MacroProgram program(text, mo);
  ReaderOptions ro = options;
  ro.block_delete = false;  // the interpreter has applied it
  GcodeReader reader(ro, file_name);
  program.run([&](const Block& b) {
    if (!reader.ended()) reader.feed(b);
  });
  Toolpath tp = reader.finish();
  if (stats) {
    *stats = reader.stats();
    // The program's lines, not the lines lexed before its first macro line was met.
    stats->lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) +
                   (!text.empty() && text.back() != '\n' ? 1 : 0);
  }
  return tp;
}

// The bytes from the stream's position to its end, if it is seekable. The stream is left where it was.
std::optional<std::streamoff> bytes_left(std::istream& in) {
  const std::istream::pos_type start = in.tellg();
  if (start == std::istream::pos_type(-1)) return std::nullopt;
  in.seekg(0, std::ios::end);
  const std::istream::pos_type end = in.tellg();
  in.clear();
  in.seekg(start);
  if (end == std::istream::pos_type(-1) || end < start) return std::nullopt;
  return end - start;
}

// The filament diameter a program states in its settings block ("; filament_diameter = 1.75", or
// "= 1.75,1.75" for several extruders, the first taken).
std::optional<double> stated_filament_diameter(std::istream& in) {
  const std::optional<std::string> value = stated_setting(in, "filament_diameter");
  if (!value) return std::nullopt;
  try {
    const double d = std::stod(*value);
    if (d > 0.1 && d < 10) return d;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> stated_setting(std::istream& in, std::string_view key) {
  const std::istream::pos_type start = in.tellg();
  if (start == std::istream::pos_type(-1)) return std::nullopt;
  in.seekg(0, std::ios::end);
  const std::istream::pos_type end = in.tellg();
  if (end == std::istream::pos_type(-1)) {
    in.clear();
    in.seekg(start);
    return std::nullopt;
  }
  const std::streamoff tail = std::min<std::streamoff>(end - start, 256 * 1024);
  in.seekg(end - tail);
  std::string text(static_cast<std::size_t>(tail), '\0');
  in.read(text.data(), tail);
  text.resize(static_cast<std::size_t>(in.gcount()));
  in.clear();
  in.seekg(start);
  const std::string line = "; " + std::string(key) + " = ";
  const std::size_t at = text.rfind(line);
  if (at == std::string::npos || (at > 0 && text[at - 1] != '\n')) return std::nullopt;
  std::string value = text.substr(at + line.size(), text.find('\n', at) - (at + line.size()));
  while (!value.empty() && (value.back() == '\r' || value.back() == ' ')) value.pop_back();
  return value;
}

Toolpath read_gcode(std::istream& in, const std::string& file_name, const ReaderOptions& given,
                    ReadStats* stats) {
  ReaderOptions options = given;
  if (options.filament_diameter_from_program)
    if (const auto d = stated_filament_diameter(in)) options.filament_diameter_mm = *d;
  GcodeReader reader(options, file_name);
  // Room for the moves a program of this size makes, so that the move list is not copied as it grows: a
  // move takes some 30 bytes of G-code or more (comments, codes), so this is seldom too little, and room
  // never used is address space, not memory.
  if (const auto bytes = bytes_left(in)) reader.reserve(static_cast<std::size_t>(*bytes / kBytesPerMove));
  int number = 0;
  std::string line, kept;
  Block block;  // reused from line to line
  bool macro = false;
  const auto lex = [&](std::string_view text) {
    ++number;
    if (kept.size() <= kMacroText) kept.append(text).push_back('\n');
    if (lex_gcode_line(text, number, file_name, block) == LineKind::kMacro) {
      if (kept.size() > kMacroText)
        throw InputError(
            {file_name, number, 0}, "gcode",
            fmt::format("macro syntax (variables, expressions or branches) after more than {} MB "
                        "of plain G-code: a macro program is read whole and must be smaller",
                        kMacroText >> 20));
      macro = true;
      return;
    }
    reader.feed(block);
  };
  std::string chunk(kChunk, '\0'), chunk_tail;
  while (!reader.ended() && !macro) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    if (got == 0) break;
    // Lines are searched for NUL bytes only in a chunk that holds one.
    const bool has_nul = std::memchr(chunk.data(), '\0', got) != nullptr;
    std::size_t at = 0;
    while (at < got && !reader.ended() && !macro) {
      const char* from = chunk.data() + at;
      const auto* nl = static_cast<const char*>(std::memchr(from, '\n', got - at));
      const std::size_t end = nl ? static_cast<std::size_t>(nl - chunk.data()) : got;
      const std::string_view piece(from, end - at);
      if (const std::size_t nul = has_nul ? piece.find('\0') : std::string_view::npos;
          nul != std::string_view::npos)
        throw InputError({file_name, number + 1, static_cast<int>(line.size() + nul) + 1}, "gcode",
                         "NUL byte in the program: this is not a text file");
      at = end;
      if (nl && line.empty()) {
        lex(piece);  // the whole line is in the chunk: lexed where it lies
      } else {
        line += piece;
        if (line.size() > kMaxLine)
          throw InputError({file_name, number + 1, 0}, "gcode",
                           fmt::format("line longer than {} bytes: this is not a G-code program", kMaxLine));
        if (nl) {
          lex(line);
          line.clear();
        }
      }
      if (nl) {
        ++at;
        if (macro) chunk_tail.assign(chunk.data() + at, got - at);
      }
    }
  }
  if (!line.empty() && !reader.ended() && !macro) lex(line);
  if (macro) {
    // The rest of the text (from where the chunk stopped), then the whole program through the interpreter.
    std::string rest(std::istreambuf_iterator<char>(in), {});
    if (rest.find('\0') != std::string::npos)
      throw InputError({file_name, 0, 0}, "gcode", "NUL byte in the program: this is not a text file");
    return read_macro(kept + chunk_tail + rest, file_name, options, stats);
  }
  Toolpath tp = reader.finish();
  if (stats) {
    *stats = reader.stats();
    stats->lines = static_cast<std::size_t>(number);
  }
  return tp;
}

}  // namespace beadtwin::gcode
