// libFuzzer target: the scenario loader (YAML through yaml-cpp, then our parameter tables, units, variants,
// sections, gates, pictures and checks). Any bytes give a scenario or an InputError, nothing else.
//
// yaml-cpp's own errors (a key asked of a scalar, a value of the wrong type) become an InputError at the
// loader's last line of defence (load_scenario_text), with yaml-cpp's words rather than the key and what was
// expected. Here they count as findings: each gets its own check where the node is read.
//
// The scenario is read as if it were /nonexistent/fuzz.yaml: machines and materials named in it are found
// among the files shipped with beadtwin, and files it names by a relative path do not exist.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "core/error.hpp"
#include "scenarios/input/scenario.hpp"

using namespace beadtwin;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    scenarios::load_scenario_text(std::string(reinterpret_cast<const char*>(data), size),
                                  "/nonexistent/fuzz.yaml");
  } catch (const InputError& e) {
    if (e.key().empty() && e.message().starts_with("unexpected YAML structure")) {
      std::fprintf(stderr, "yaml-cpp's error reached the loader's last line of defence: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
