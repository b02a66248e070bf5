// libFuzzer target: the Fanuc macro interpreter on its own (parse, then run), without the G-code reader
// behind it, so the fuzzer spends its time on expressions, loops, jumps and subprogram calls. Any bytes give
// blocks or an InputError, nothing else.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.hpp"
#include "gcode/macro.hpp"

using namespace beadtwin;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  gcode::MacroOptions options;
  options.max_steps = 20'000;  // an endless loop is found quickly, not after the fuzzer's timeout
  options.file_name = "fuzz.nc";
  try {
    const gcode::MacroProgram program(std::string_view(reinterpret_cast<const char*>(data), size), options);
    program.run([](const gcode::Block&) {});
  } catch (const InputError&) {
  }
  return 0;
}
