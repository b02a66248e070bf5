// The sweep's junit.xml (scenarios/sweep.hpp): a test suite per variant with a test case per gate, and an
// error for a variant that did not run to the end.
#include <fmt/format.h>

#include "scenarios/report_text.hpp"
#include "scenarios/sweep.hpp"

namespace beadtwin::scenarios {

std::string sweep_junit_xml(const SweepResult& r) {
  std::size_t tests = 0, failures = 0, errors = 0;
  for (const SweepRecord& rec : r.records) {
    if (!rec.ran()) {
      ++tests, ++errors;
      continue;
    }
    for (const GateResult& g : rec.gates) ++tests, failures += g.passed ? 0 : 1;
  }
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x += fmt::format(
      "<testsuites name=\"beadtwin sweep\" tests=\"{}\" failures=\"{}\" errors=\"{}\" time=\"{:.3f}\">\n",
      tests, failures, errors, r.wall_time_s);
  const std::string suite = esc(r.scenario_name);
  for (const SweepRecord& rec : r.records) {
    const std::string name = esc(rec.name);
    if (!rec.ran()) {
      x += fmt::format(
          "  <testsuite name=\"{0}.{1}\" tests=\"1\" failures=\"0\" errors=\"1\" time=\"{2:.3f}\">\n"
          "    <testcase classname=\"{0}.{1}\" name=\"run\">\n      <error message=\"exit code {3}\" "
          "type=\"run\">{4}</error>\n    </testcase>\n  </testsuite>\n",
          suite, name, rec.wall_time_s, rec.exit_code, esc(rec.message));
      continue;
    }
    x += junit_suite(r.scenario_name, rec.name, rec.gates, rec.wall_time_s);
  }
  x += "</testsuites>\n";
  return x;
}

}  // namespace beadtwin::scenarios
