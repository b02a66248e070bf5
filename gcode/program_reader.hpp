// A G-code program's text into the Toolpath IR: read_gcode streams it line by line through the lexer
// (gcode/lexer.hpp) into the block reader (gcode/block_reader.hpp says what each block means), or, when a
// line holds macro syntax, runs the whole program through the Fanuc macro interpreter (gcode/macro.hpp)
// into it. stated_setting reads a setting that PrusaSlicer and Slic3r write at a program's end.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>

#include "core/toolpath.hpp"
#include "gcode/block_reader.hpp"
#include "gcode/reader_options.hpp"

namespace beadtwin::gcode {

// The value of a setting a program states in the block PrusaSlicer and Slic3r write at its end ("; key =
// value"), as written, found in the last 256 kB of a seekable stream without reading the rest; the stream
// is left where it was. None when the stream cannot seek or states no such setting.
std::optional<std::string> stated_setting(std::istream& in, std::string_view key);

// Reads the program in `in` line by line (lexer, then reader) until its end or M2/M30; a program with macro
// syntax is read whole and run by the macro interpreter instead. Throws InputError for a file that is not
// text (NUL bytes or a line over 1 MB), macro syntax after more than 8 MB of plain G-code, a macro program
// the interpreter refuses, and everything GcodeReader::feed refuses. `stats`, if given, receives the reading
// statistics.
Toolpath read_gcode(std::istream& in, const std::string& file_name, const ReaderOptions& options = {},
                    ReadStats* stats = nullptr);

}  // namespace beadtwin::gcode
