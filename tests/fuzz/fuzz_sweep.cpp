// libFuzzer target: what a sweep reads from its user (scenarios/input/sweep_spec.hpp): a combinations file
// (YAML through yaml-cpp, then lists of setting maps), and the same bytes as a --set KEY=V1,V2,... option and
// as a
// --sort metric. Any bytes give combinations or an InputError, nothing else.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/error.hpp"
#include "scenarios/input/sweep_spec.hpp"

using namespace beadtwin;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)scenarios::parse_sweep_combinations(text, "/nonexistent/combinations.yaml");
  } catch (const InputError& e) {
    if (e.key().empty() && e.message().starts_with("unexpected YAML structure")) {
      std::fprintf(stderr, "yaml-cpp's error escaped the combinations reader: %s\n", e.what());
      std::abort();
    }
  }
  try {
    (void)scenarios::parse_sweep_axis(text);
  } catch (const InputError&) {
  }
  try {
    (void)scenarios::parse_objective(text, "--sort");
  } catch (const InputError&) {
  }
  return 0;
}
