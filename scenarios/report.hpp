// Reports: report.json for machines, report.html for people, junit.xml for CI systems and
// summary.md for a pull-request comment. All written atomically.
#pragma once

#include <filesystem>
#include <string>

#include "scenarios/result.hpp"

namespace beadtwin::scenarios {

std::string report_json(const RunResult& result);
std::string report_html(const RunResult& result);
std::string junit_xml(const RunResult& result);
std::string summary_md(const RunResult& result);

// Writes the four reports into `dir`.
void write_reports(const RunResult& result, const std::filesystem::path& dir);

}  // namespace beadtwin::scenarios
