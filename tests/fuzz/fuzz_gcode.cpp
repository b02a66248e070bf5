// libFuzzer target: the G-code reader (read_gcode: lexer, reader, arcs, and the macro interpreter when the
// program has macro lines). The contract under test: any bytes give a toolpath or an InputError, nothing
// else: no crash, no sanitizer finding, no other exception, no hang, no unbounded memory.
//
// The program's length in bytes, modulo 3, picks the reader's dialect, so the fuzzer explores each from any
// seed: 0 the defaults (RepRap E words, millimetres), 1 inches and relative E, 2 a roller machine's (melt
// M3/M5, dwell in seconds, a default bead for moves without E words, the roller down from the start).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "gcode/program_reader.hpp"

using namespace beadtwin;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  gcode::ReaderOptions options;
  options.max_macro_steps = 20'000;  // an endless loop is found quickly, not after the fuzzer's timeout
  options.max_moves = 1'000'000;     // the limit is tested, not the machine's memory
  switch (size % 3) {
    case 1:
      options.inches = true;
      options.absolute_e = false;
      break;
    case 2:
      options.melt_on = {"M3"};
      options.melt_off = {"M5"};
      options.dwell_p_seconds = true;
      options.default_bead_width_mm = 25.0;
      options.default_layer_height_mm = 5.0;
      options.roller_down_at_start = true;
      break;
    default:
      break;
  }
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    gcode::read_gcode(in, "fuzz.gcode", options);
  } catch (const InputError&) {
  }
  return 0;
}
