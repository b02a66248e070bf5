// Reports: report.json for machines, report.html for people, junit.xml for CI systems and
// summary.md for a pull-request comment. All written atomically. Each format has its own file
// (report_json.cpp, report_html.cpp, report_junit.cpp, report_summary.cpp); the metrics they show are
// declared in scenarios/input/metrics.hpp.
#pragma once

#include <filesystem>
#include <string>

#include "scenarios/input/result.hpp"

namespace beadtwin::scenarios {

std::string report_json(const RunResult& result);
std::string report_html(const RunResult& result);
std::string junit_xml(const RunResult& result);
std::string summary_md(const RunResult& result);

// Writes the four reports into `dir`.
void write_reports(const RunResult& result, const std::filesystem::path& dir);

}  // namespace beadtwin::scenarios
