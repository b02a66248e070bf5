// junit.xml (scenarios/report.hpp): a test suite per variant and a test case per gate, for CI systems.
#include <fmt/format.h>

#include "scenarios/report.hpp"
#include "scenarios/report_text.hpp"

namespace beadtwin::scenarios {

std::string junit_suite(const std::string& scenario, const std::string& variant,
                        const std::vector<GateResult>& gates, double seconds) {
  int failures = 0;
  for (const auto& g : gates) failures += g.passed ? 0 : 1;
  const std::string classname = esc(scenario) + "." + esc(variant);
  std::string x =
      fmt::format("  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"0\" time=\"{:.3f}\">\n",
                  classname, gates.size(), failures, seconds);
  for (const auto& g : gates) {
    x += fmt::format("    <testcase classname=\"{}\" name=\"{}\"", classname, esc(g.expr));
    if (g.passed) {
      x += "/>\n";
    } else {
      x += fmt::format(">\n      <failure message=\"{0}\" type=\"gate\">{0}</failure>\n    </testcase>\n",
                       esc(g.message));
    }
  }
  return x + "  </testsuite>\n";
}

std::string junit_xml(const RunResult& result) {
  int tests = 0, failures = 0;
  for (const auto& v : result.variants)
    for (const auto& g : v.gates) ++tests, failures += g.passed ? 0 : 1;
  const std::string name = result.scenario ? result.scenario->name : "beadtwin";
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x += fmt::format(
      "<testsuites name=\"beadtwin\" tests=\"{}\" failures=\"{}\" errors=\"0\" time=\"{:.3f}\">\n", tests,
      failures, result.wall_time_s);
  for (const auto& v : result.variants) x += junit_suite(name, v.name, v.gates, v.wall_time_s);
  x += "</testsuites>\n";
  return x;
}

}  // namespace beadtwin::scenarios
