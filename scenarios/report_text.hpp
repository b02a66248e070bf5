// Text the report writers share (the run's reports and the sweep's): escaping for HTML and XML, Markdown
// table cells, numbers as JSON and as times, the pages' beginning and end, a plot for report_plots.js and a
// variant's junit.xml test suite.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenarios/input/result.hpp"

namespace beadtwin::scenarios {

// `s` escaped for HTML and XML text and attribute values (control characters XML refuses become '?').
std::string esc(std::string_view s);

// A table cell for Markdown: pipes escaped, line breaks as spaces.
std::string md(std::string_view text);

// `v` for JSON: null where it is not finite (JSON has no NaN or infinity).
nlohmann::json number_or_null(double v);

// A duration `s` in seconds as h:mm:ss, rounded to the second.
std::string hms(double s);

// An HTML page up to its body: the title (escaped here) and the reports' style sheet, so report.html and
// sweep.html look alike.
std::string html_page_start(std::string_view title);
// The end of such a page: the scripts that draw its plots (scenarios/report_scripts.hpp), placed last so
// the plots' data is in place when they run.
std::string html_page_end();

// A plot drawn by report_plots.js: its data as JSON in a script element (with "<" escaped, so no value can
// end the element), drawn into a canvas after it when the page loads; for readers without scripts, a line
// saying the same numbers are in `where_else` ("the table below").
std::string plot_html(const nlohmann::json& spec, std::string_view where_else);

// junit.xml's <testsuite> for one variant's gates: a test case per gate, a failure per failed one;
// `seconds` is the variant's wall time.
std::string junit_suite(const std::string& scenario, const std::string& variant,
                        const std::vector<GateResult>& gates, double seconds);

}  // namespace beadtwin::scenarios
