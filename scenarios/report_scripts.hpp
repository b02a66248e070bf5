// The scripts report.html embeds, built into the binary (scenarios/CMakeLists.txt): Chart.js from Debian's
// libjs-chart.js, and scenarios/report_plots.js, which draws the report's plots with it.
#pragma once

#include <string_view>

namespace beadtwin::scenarios {

std::string_view chartjs_source();
std::string_view report_plots_source();

}  // namespace beadtwin::scenarios
