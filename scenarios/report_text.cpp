// Text the report writers share (scenarios/report_text.hpp).
#include "scenarios/report_text.hpp"

#include <cmath>

#include <fmt/format.h>

#include "scenarios/report_scripts.hpp"

namespace beadtwin::scenarios {
namespace {

// The style sheet of report.html and sweep.html, a <style> element.
constexpr std::string_view kStyle = R"(<style>
body{font-family:system-ui,sans-serif;margin:2em auto;max-width:1100px;color:#222;padding:0 1em}
h1{margin-bottom:.2em} .verdict{display:inline-block;padding:.2em .7em;border-radius:4px;color:#fff;font-weight:600}
.pass{background:#2e8b57}.fail{background:#c0392b} table{border-collapse:collapse;margin:1em 0;font-size:13px}
td,th{border:1px solid #ddd;padding:3px 8px;text-align:right} th{background:#f4f5f7} td.l,th.l{text-align:left}
tr.hot td{background:#fde2df} tr.cold td{background:#dfe8f8} tr.marginal td{background:#fdf0d5} img{max-width:100%;border:1px solid #ddd}
.legend span{display:inline-block;width:12px;height:12px;margin:0 4px 0 12px;vertical-align:middle}
details{margin:1em 0} .muted{color:#777} .plot{position:relative;height:300px;margin:1em 0}
td.better{background:#dff2e4} td.worse{background:#fbe1dd} td.diff{background:#fff3cc} .delta{color:#555;font-size:11px}
</style>
)";

}  // namespace

std::string esc(std::string_view s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      // Tabs and line breaks as references, which keep them in attribute values (XML normalises the
      // characters themselves to spaces there).
      case '\t':
        out += "&#9;";
        break;
      case '\n':
        out += "&#10;";
        break;
      case '\r':
        out += "&#13;";
        break;
      default:
        // XML 1.0 allows no other control character: one would make junit.xml unreadable.
        out += static_cast<unsigned char>(c) < 0x20 ? '?' : c;
    }
  }
  return out;
}

std::string md(std::string_view text) {
  std::string out;
  for (const char c : text) {
    if (c == '|') out += '\\';
    out += c == '\n' ? ' ' : c;
  }
  return out;
}

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

std::string hms(double s) {
  const long t = std::lround(s);
  return fmt::format("{}:{:02}:{:02}", t / 3600, (t / 60) % 60, t % 60);
}

std::string html_page_start(std::string_view title) {
  return "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + esc(title) +
         "</title>" + std::string(kStyle) + "</head><body>\n";
}

std::string html_page_end() {
  return "<script>" + std::string(chartjs_source()) + "</script>\n<script>" +
         std::string(report_plots_source()) + "</script>\n</body></html>\n";
}

std::string plot_html(const nlohmann::json& spec, std::string_view where_else) {
  std::string text = spec.dump();
  std::string safe;
  safe.reserve(text.size());
  for (const char c : text) safe += c == '<' ? std::string("\\u003c") : std::string(1, c);
  return "<script type=\"application/json\" class=\"beadtwin-plot\">" + safe +
         "</script><noscript><p class=muted>This plot is drawn by a script; the same numbers are in " +
         esc(where_else) + ".</p></noscript>";
}

}  // namespace beadtwin::scenarios
