// report.html as a browser shows it: headless Chromium opens the report of a small two-variant
// run, and the page loads without console errors, shows the variants table and the pictures, and draws its
// plots; a screenshot of the whole page, saved beside the report, shows them too.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "render/image.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/run.hpp"
#include "scenarios/sweep.hpp"
#include "tests/chromium.hpp"
#include "tests/scenarios/small_box.hpp"

namespace beadtwin::scenarios {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::Chromium;

// Two variants of the small box with the default pictures: a few seconds' run.
const std::string kTwoVariants = testing::small_box("browser-box") + R"(variants:
  - name: fast
  - name: slow
    set: {sections.walls.speed: 10 mm/s, sections.floor.speed: 10 mm/s}
)";

// The width the report is read at: wider than its 1100 px column.
constexpr int kViewportWidth = 1200;
// Chromium draws no taller a screenshot than its largest texture.
constexpr int kMaxScreenshotHeight = 16000;
// For each reply or event; a starting browser on a loaded 2-core machine takes a few seconds.
constexpr std::chrono::seconds kBrowserTimeout{30};

fs::path chromium_on_path() {
  return testing::find_on_path({"chromium", "chromium-browser"});
}
constexpr const char* kNoChromium =
    "chromium is not on PATH (Debian: apt-get install chromium, as tools/setup.sh --tests does)";

// Chromium's path; skips the test without it, but fails it in CI (CI set), where tools/setup.sh --tests
// installed it: a browser test skipped there would pass unseen.
#define BEADTWIN_REQUIRE_CHROMIUM(exe)                         \
  const fs::path exe = chromium_on_path();                     \
  if (exe.empty() && std::getenv("CI")) FAIL() << kNoChromium; \
  if (exe.empty()) GTEST_SKIP() << kNoChromium

// A page open in its own tab: the session that drives it, and where its events start in events().
struct Page {
  std::string session;
  std::size_t first_event = 0;
};

// The value of a JavaScript expression in the page (a promise's, once it settles). Throws
// std::runtime_error when it throws.
json evaluate(Chromium& browser, const Page& page, const std::string& expression) {
  const json result = browser.call(
      "Runtime.evaluate", {{"expression", expression}, {"awaitPromise", true}, {"returnByValue", true}},
      page.session);
  if (result.contains("exceptionDetails"))
    throw std::runtime_error("script threw: " + result["exceptionDetails"].dump());
  return result["result"].value("value", json());
}

// Waits until the page has loaded and drawn two frames since, so scripts that draw at load (charts into
// their canvases) have drawn, and returns the page's address.
std::string settle(Chromium& browser, const Page& page) {
  return evaluate(browser, page, R"(new Promise(resolve => {
    const frames = () => requestAnimationFrame(() => requestAnimationFrame(() => resolve(location.href)));
    if (document.readyState === 'complete') frames(); else addEventListener('load', frames, {once: true});
  }))")
      .get<std::string>();
}

void set_viewport(Chromium& browser, const Page& page, int height) {
  browser.call("Emulation.setDeviceMetricsOverride",
               {{"width", kViewportWidth}, {"height", height}, {"deviceScaleFactor", 1}, {"mobile", false}},
               page.session);
}

// Opens `file` in a new tab with the console, exceptions and the browser's log reported, and waits for it to
// load and settle.
Page open_page(Chromium& browser, const fs::path& file) {
  const std::string target = browser.call("Target.createTarget", {{"url", "about:blank"}})["targetId"];
  Page page;
  page.session =
      browser.call("Target.attachToTarget", {{"targetId", target}, {"flatten", true}})["sessionId"];
  page.first_event = browser.events().size();
  for (const char* domain : {"Page.enable", "Runtime.enable", "Log.enable"})
    browser.call(domain, json::object(), page.session);
  set_viewport(browser, page, 900);
  const std::size_t before_navigation = browser.events().size();
  const std::string url = testing::file_url(file);
  const json navigated = browser.call("Page.navigate", {{"url", url}}, page.session);
  if (navigated.contains("errorText"))
    throw std::runtime_error("cannot open " + url + ": " + navigated["errorText"].get<std::string>());
  browser.wait_for("Page.loadEventFired", page.session, before_navigation);
  const std::string href = settle(browser, page);
  if (href != url) throw std::runtime_error("the page settled at " + href + ", not " + url);
  return page;
}

// What the page reported as going wrong: console errors and warnings, uncaught exceptions, and the errors
// of the browser's log (a picture or script that failed to load), one line each.
std::vector<std::string> console_problems(const Chromium& browser, const Page& page) {
  std::vector<std::string> problems;
  const auto& events = browser.events();
  for (std::size_t i = page.first_event; i < events.size(); ++i) {
    const json& e = events[i];
    if (e.value("sessionId", "") != page.session) continue;
    const std::string method = e.value("method", "");
    const json& p = e["params"];
    if (method == "Runtime.consoleAPICalled") {
      const std::string type = p.value("type", "");
      if (type != "error" && type != "warning" && type != "assert") continue;
      std::string text = "console." + type + ":";
      for (const json& arg : p["args"])
        text += " " + (arg.contains("value") ? (arg["value"].is_string() ? arg["value"].get<std::string>()
                                                                         : arg["value"].dump())
                                             : arg.value("description", arg.value("type", "")));
      problems.push_back(text);
    } else if (method == "Runtime.exceptionThrown") {
      const json& d = p["exceptionDetails"];
      problems.push_back("exception: " + d.value("text", "") + " " +
                         d.value("exception", json::object()).value("description", "") + " at " +
                         d.value("url", "") + ":" + std::to_string(d.value("lineNumber", -1) + 1));
    } else if (method == "Log.entryAdded" && p["entry"].value("level", "") == "error") {
      problems.push_back("log (" + p["entry"].value("source", "") + "): " + p["entry"].value("text", "") +
                         " " + p["entry"].value("url", ""));
    }
  }
  return problems;
}

// What report_html.cpp writes, as the page lays it out: the variants table with the first cell of each data
// row, every picture with whether it loaded, every plot (an inline SVG or a chart's canvas; not the SVG
// inside another) with its box, and the page's size. Boxes are in page pixels, {x, y, width, height}. A plot
// in a closed <details> is not laid out, so it is left out.
const char* const kInspect = R"((() => {
  const box = e => {
    const r = e.getBoundingClientRect();
    return {x: r.left + scrollX, y: r.top + scrollY, width: r.width, height: r.height};
  };
  const table = document.querySelector('table.variants');
  return {
    table: table && {
      box: box(table),
      rows: [...table.rows].filter(r => r.cells.length && r.cells[0].tagName === 'TD')
                           .map(r => r.cells[0].textContent)
    },
    images: [...document.images].map(i => ({
      src: i.getAttribute('src'), complete: i.complete, natural_width: i.naturalWidth, box: box(i)
    })),
    plots: [...document.querySelectorAll('svg, canvas')]
             .filter(e => !e.parentElement.closest('svg') && !e.closest('details:not([open])'))
             .map(e => ({kind: e.tagName.toLowerCase(), label: e.getAttribute('aria-label') || e.id || '',
                         box: box(e)})),
    page: {width: document.documentElement.scrollWidth, height: document.documentElement.scrollHeight}
  };
})())";

// Pictures that did not load and plots drawn at no size, one line each.
std::vector<std::string> layout_problems(const json& inspection) {
  std::vector<std::string> problems;
  for (const json& image : inspection["images"])
    if (!image["complete"].get<bool>() || image["natural_width"].get<int>() <= 0)
      problems.push_back("picture not loaded: " + image["src"].get<std::string>());
  for (const json& plot : inspection["plots"])
    if (plot["box"]["width"].get<double>() <= 0 || plot["box"]["height"].get<double>() <= 0)
      problems.push_back("plot of no size: <" + plot["kind"].get<std::string>() + "> " +
                         plot["label"].get<std::string>());
  return problems;
}

// The whole page as a PNG at `path`, read back through OpenImageIO. The viewport is made as tall as the
// page first (so the boxes `inspection` then gives are the screenshot's pixels) and the page settles
// again, since charts redraw when their viewport changes.
render::Image screenshot(Chromium& browser, const Page& page, const fs::path& path, json& inspection) {
  const int height =
      std::min(evaluate(browser, page, kInspect)["page"]["height"].get<int>(), kMaxScreenshotHeight);
  set_viewport(browser, page, height);
  settle(browser, page);
  inspection = evaluate(browser, page, kInspect);
  const json shot = browser.call("Page.captureScreenshot", {{"format", "png"}}, page.session);
  std::ofstream(path, std::ios::binary) << testing::base64_decode(shot["data"].get<std::string>());
  return render::read_image(path);
}

// The share of the pixels in `box` (page pixels, clipped to the image) for which `pick` holds; 0 for a
// box outside the image.
double share(const render::Image& image, const json& box, const std::function<bool(render::Rgb)>& pick) {
  const int x0 = std::max(0, static_cast<int>(std::ceil(box["x"].get<double>())));
  const int y0 = std::max(0, static_cast<int>(std::ceil(box["y"].get<double>())));
  const int x1 = std::min(image.width, static_cast<int>(box["x"].get<double>() + box["width"].get<double>()));
  const int y1 =
      std::min(image.height, static_cast<int>(box["y"].get<double>() + box["height"].get<double>()));
  if (x1 <= x0 || y1 <= y0) return 0;
  long hits = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) hits += pick(image.at(x, y)) ? 1 : 0;
  return static_cast<double>(hits) / (static_cast<double>(x1 - x0) * (y1 - y0));
}

// Ink: anything darker than the page's white and the table's palest fills (#f4f5f7 headings).
bool ink(render::Rgb c) {
  return std::min({c.r, c.g, c.b}) < 0.9f;
}
// Text: dark.
bool dark(render::Rgb c) {
  return std::max({c.r, c.g, c.b}) < 0.5f;
}
// Colour, not white or grey: the part's colours against the pictures' grey backdrop.
bool coloured(render::Rgb c) {
  return std::max({c.r, c.g, c.b}) - std::min({c.r, c.g, c.b}) > 0.25f;
}

std::string lines(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& item : items) s += "\n  " + item;
  return s;
}

// A page as the browser showed it: what kInspect found, a screenshot of the whole page (saved as
// `shot_name` beside it, its path printed), and what the page reported as going wrong.
struct Shown {
  json inspection;
  render::Image shot;
  std::vector<std::string> problems;
};
Shown show(const fs::path& exe, const fs::path& out, const std::string& page_name,
           const std::string& shot_name) {
  Shown s;
  {
    Chromium browser(exe, out / "chromium-profile", out / "chromium.log", kBrowserTimeout);
    const Page page = open_page(browser, out / page_name);
    s.shot = screenshot(browser, page, out / shot_name, s.inspection);
    s.problems = console_problems(browser, page);
  }
  std::error_code ignored;  // the crash handler, which outlives the browser a moment, may still write there
  fs::remove_all(out / "chromium-profile", ignored);
  std::cout << "screenshot: " << (out / shot_name).string() << "\n";
  return s;
}

TEST(ReportInBrowser, ShowsTheTableAndThePicturesWithoutErrors) {
  BEADTWIN_REQUIRE_CHROMIUM(exe);
  const fs::path out = fs::temp_directory_path() / "beadtwin_report_browser";
  fs::remove_all(out);
  RunOptions o;
  o.out_dir = out;
  const RunResult r = run_scenario(load_scenario_text(kTwoVariants, "browser.yaml"), o);
  ASSERT_EQ(r.variants.size(), 2u);

  const auto [inspection, shot, problems] = show(exe, out, "report.html", "report-screenshot.png");

  EXPECT_TRUE(problems.empty()) << "the page reported:" << lines(problems);
  EXPECT_TRUE(layout_problems(inspection).empty()) << lines(layout_problems(inspection));

  // The variants table: a row per variant, in order.
  ASSERT_TRUE(inspection["table"].is_object()) << "no table.variants in the report";
  const json& rows = inspection["table"]["rows"];
  ASSERT_EQ(rows.size(), r.variants.size()) << rows.dump();
  for (std::size_t i = 0; i < r.variants.size(); ++i)
    EXPECT_EQ(rows[i].get<std::string>().rfind(r.variants[i].name, 0), 0u)
        << rows[i] << " " << r.variants[i].name;

  // Each variant's pictures and the comparison sheets, all shown; the substrate plot of each variant.
  std::size_t pictures = r.sheets.size();
  for (const VariantResult& v : r.variants) pictures += v.images.size();
  EXPECT_EQ(inspection["images"].size(), pictures);
  EXPECT_GE(inspection["plots"].size(), r.variants.size());

  // The screenshot shows them: the table has text, the first picture is in colour, no picture is blank
  // (a broken picture is a small icon on white) and every plot has its lines and labels. Measured here:
  // the table 30 % ink and 5 % text; the first picture (a comparison sheet: two small parts under their
  // titles and legends) 5.5 % colour; every picture 59-77 % ink on its grey backdrop; the plots 2.6-31 % ink.
  ASSERT_EQ(shot.width, kViewportWidth);
  const json& table = inspection["table"]["box"];
  EXPECT_GT(share(shot, table, ink), 0.05) << "table at " << table;
  EXPECT_GT(share(shot, table, dark), 0.02) << "table at " << table;
  ASSERT_FALSE(inspection["images"].empty());
  const json& first = inspection["images"][0];
  EXPECT_GT(share(shot, first["box"], coloured), 0.02) << first;
  // Boxes below the screenshot (a page taller than it) are not checked.
  const auto shown = [&](const json& box) {
    return box["y"].get<double>() + box["height"].get<double>() <= shot.height;
  };
  for (const json& image : inspection["images"]) {
    if (shown(image["box"])) {
      EXPECT_GT(share(shot, image["box"], ink), 0.2) << image;
    }
  }
  for (const json& plot : inspection["plots"]) {
    if (shown(plot["box"])) {
      EXPECT_GT(share(shot, plot["box"], ink), 0.01) << plot;
    }
  }
}

// The checks above can fail: a page with a missing picture, a console error and warning, an uncaught
// exception and plots of no size (an SVG and a chart's canvas) has each of them reported.
TEST(ReportInBrowser, ReportsWhatGoesWrongOnAPage) {
  BEADTWIN_REQUIRE_CHROMIUM(exe);
  const fs::path out = fs::temp_directory_path() / "beadtwin_report_browser_broken";
  fs::remove_all(out);
  fs::create_directories(out);
  std::ofstream(out / "broken.html") << R"(<!doctype html><html lang="en"><head><meta charset="utf-8">
<title>broken</title></head><body>
<table class=variants><tr><th>variant</th></tr><tr><td>only</td></tr></table>
<p><img src="missing.png" alt="missing"></p>
<svg width="0" height="0" aria-label="empty plot"></svg>
<canvas id="chart" width="300" height="0"></canvas>
<script>console.error('deliberate error'); console.warn('deliberate warning');
throw new Error('deliberate exception');</script>
</body></html>
)";
  json inspection;
  std::vector<std::string> problems;
  {
    Chromium browser(exe, out / "chromium-profile", out / "chromium.log", kBrowserTimeout);
    const Page page = open_page(browser, out / "broken.html");
    inspection = evaluate(browser, page, kInspect);
    problems = console_problems(browser, page);
  }
  std::error_code ignored;  // the crash handler, which outlives the browser a moment, may still write there
  fs::remove_all(out / "chromium-profile", ignored);

  const std::string all = lines(problems);
  for (const char* expected : {"console.error: deliberate error", "console.warning: deliberate warning",
                               "deliberate exception", "missing.png"})
    EXPECT_NE(all.find(expected), std::string::npos) << expected << " not in:" << all;
  EXPECT_EQ(layout_problems(inspection),
            (std::vector<std::string>{"picture not loaded: missing.png", "plot of no size: <svg> empty plot",
                                      "plot of no size: <canvas> chart"}));
  EXPECT_EQ(inspection["table"]["rows"], json({"only"}));
}

// sweep.html as a browser shows it: the Pareto plot drawn, the variants table, no errors. The
// records are made up (twelve variants of a two-parameter grid, one failed to run), so no run is needed.
TEST(ReportInBrowser, ShowsASweepsParetoPlotAndTable) {
  BEADTWIN_REQUIRE_CHROMIUM(exe);
  const fs::path out = fs::temp_directory_path() / "beadtwin_sweep_browser";
  fs::remove_all(out);
  fs::create_directories(out);
  SweepResult r;
  r.scenario_name = "browser sweep";
  r.scenario_file = "box.yaml";
  r.base_variant = "baseline";
  r.axes = {{"sections.walls.layer_time", {"30 s", "60 s", "90 s", "120 s"}},
            {"sections.walls.bead_width", {"18 mm", "20 mm", "22 mm"}}};
  r.gates = {parse_gate_text("interfaces.too_cold_fraction < 0.2", {"t", 1, 1})};
  r.sort = {"print_time_s", false};
  r.pareto = {{"print_time_s", false}, {"interfaces.too_cold_fraction", false}};
  r.engine = "1 local process";
  const std::vector<SweepPoint> points = expand_sweep(r.axes, {});
  for (std::size_t i = 0; i < points.size(); ++i) {
    SweepRecord rec;
    rec.name = points[i].name;
    rec.settings = points[i].settings;
    rec.status = SweepStatus::kPassed;
    rec.exit_code = 0;
    const double layer = 30.0 * static_cast<double>(i / 3 + 1),
                 width = 18.0 + 2.0 * static_cast<double>(i % 3);
    // Longer layer times print slower with fewer cold joints; wider beads faster with more: a trade-off.
    rec.values = {{"print_time_s", 3600.0 + 40.0 * layer - 50.0 * width},
                  {"interfaces.too_cold_fraction", 0.35 - 0.0025 * layer + 0.004 * (width - 18.0)}};
    r.records.push_back(rec);
  }
  r.records[7].status = SweepStatus::kFailed;
  r.records[7].values.clear();
  r.records[7].message = "error: deliberately failed";
  apply_sweep_gates(r.records, r.gates);
  write_sweep_reports(r, out);

  const auto [inspection, shot, problems] = show(exe, out, "sweep.html", "sweep-screenshot.png");

  EXPECT_TRUE(problems.empty()) << "the page reported:" << lines(problems);
  // The links to the variants' own reports are missing here (no run made them): the layout check reads
  // only pictures and plots.
  EXPECT_TRUE(layout_problems(inspection).empty()) << lines(layout_problems(inspection));
  ASSERT_TRUE(inspection["table"].is_object());
  EXPECT_EQ(inspection["table"]["rows"].size(), points.size());
  ASSERT_EQ(inspection["plots"].size(), 1u);
  const json& plot = inspection["plots"][0]["box"];
  EXPECT_GT(plot["height"].get<double>(), 100) << plot;
  EXPECT_GT(share(shot, plot, ink), 0.01) << plot;
  EXPECT_GT(share(shot, plot, coloured), 0.001) << plot;  // the front's blue, the points' green and red
}

}  // namespace
}  // namespace beadtwin::scenarios
