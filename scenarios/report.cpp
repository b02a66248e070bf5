// The four reports of a run, written together (scenarios/report.hpp); each format has its own file:
// report_json.cpp, report_html.cpp, report_junit.cpp, report_summary.cpp.
#include "scenarios/report.hpp"

#include "core/atomic_file.hpp"

namespace beadtwin::scenarios {

void write_reports(const RunResult& result, const std::filesystem::path& dir) {
  write_file_atomic(dir / "report.json", report_json(result));
  write_file_atomic(dir / "report.html", report_html(result));
  write_file_atomic(dir / "junit.xml", junit_xml(result));
  write_file_atomic(dir / "summary.md", summary_md(result));
}

}  // namespace beadtwin::scenarios
