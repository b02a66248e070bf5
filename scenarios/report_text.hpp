// Text the report writers share (report.cpp, sweep.cpp): escaping for HTML and XML, Markdown table cells,
// a plot for report_plots.js, a variant's junit.xml test suite and the style sheet.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenarios/result.hpp"

namespace beadtwin::scenarios {

// `s` escaped for HTML and XML text and attribute values (control characters XML refuses become '?').
std::string esc(std::string_view s);

// A table cell for Markdown: pipes escaped, line breaks as spaces.
std::string md(std::string_view text);

// A plot drawn by report_plots.js: its data as JSON in a script element (with "<" escaped, so no value can
// end the element), drawn into a canvas after it when the page loads; for readers without scripts, a line
// saying the same numbers are in `where_else` ("the table below").
std::string plot_html(const nlohmann::json& spec, std::string_view where_else);

// junit.xml's <testsuite> for one variant's gates: a test case per gate, a failure per failed one.
std::string junit_suite(const std::string& scenario, const std::string& variant,
                        const std::vector<GateResult>& gates, double seconds);

// The reports' style sheet, a <style> element: report.html and sweep.html look alike.
std::string_view report_style();

}  // namespace beadtwin::scenarios
