// report.html (scenarios/report.hpp): the run for people, a page per run with the variants side by side and
// then each variant's gates, pictures, plots and tables.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "render/colormap.hpp"
#include "scenarios/colours.hpp"
#include "scenarios/gate_results.hpp"
#include "scenarios/report.hpp"
#include "scenarios/report_columns.hpp"
#include "scenarios/report_text.hpp"
#include "scenarios/run.hpp"

namespace beadtwin::scenarios {
namespace {

// Defects listed by position (report.json has the rest).
constexpr std::size_t kDefectsInHtml = 20;

using nlohmann::json;

// A row of a two-column table: what, and its value.
std::string table_row(std::string_view key, const std::string& value) {
  return fmt::format("<tr><td class=l>{}</td><td>{}</td></tr>", key, value);
}

// The deposit's defects: how many of each kind, and the first ones with where they are.
std::string defects_html(const std::vector<sim::Defect>& defects) {
  if (defects.empty()) return "<p>The deposit found no defects.</p>";
  std::map<std::string, int> counts;
  for (const sim::Defect& d : defects) ++counts[std::string(sim::to_string(d.kind))];
  std::string summary;
  for (const auto& [kind, n] : counts)
    summary += fmt::format("{}{} {}", summary.empty() ? "" : ", ", n, kind);
  std::string h = fmt::format(
      "<details><summary>Defects: {}</summary><table><tr><th class=l>kind</th><th>layer</th>"
      "<th>x, y, z mm</th><th>program line</th><th class=l>what</th></tr>",
      esc(summary));
  for (std::size_t i = 0; i < std::min(defects.size(), kDefectsInHtml); ++i) {
    const sim::Defect& d = defects[i];
    h += fmt::format(
        "<tr><td class=l>{}</td><td>{}</td><td>{:.1f}, {:.1f}, {:.1f}</td><td>{}</td><td "
        "class=l>{}</td></tr>",
        sim::to_string(d.kind), d.layer, d.position_mm.x(), d.position_mm.y(), d.position_mm.z(),
        d.source_line > 0 ? std::to_string(d.source_line) : "–", esc(d.detail));
  }
  if (defects.size() > kDefectsInHtml)
    h += fmt::format("<tr><td class=l colspan=5>… and {} more in report.json</td></tr>",
                     defects.size() - kDefectsInHtml);
  return h + "</table></details>";
}

std::string byte_size(std::uintmax_t bytes) {
  const double b = static_cast<double>(bytes);
  if (b >= 1e9) return fmt::format("{:.2f} GB", b / 1e9);
  if (b >= 1e6) return fmt::format("{:.1f} MB", b / 1e6);
  if (b >= 1e3) return fmt::format("{:.0f} kB", b / 1e3);
  return fmt::format("{} bytes", bytes);
}

// How many times the skin's triangles a bead-by-bead STL would hold (triangles, not bytes: a PLY stores a
// triangle in about half the bytes of an STL).
std::string ratio_text(const ExportedFiles& f) {
  const double ratio = static_cast<double>(f.bead_stl_triangles) /
                       static_cast<double>(std::max<std::size_t>(f.skin_triangles, 1));
  return ratio >= 10 ? fmt::format("{:.0f}", ratio) : fmt::format("{:.2g}", ratio);
}

// Links to the files for other programs, with what they hold.
std::string files_html(const VariantResult& r) {
  const ExportedFiles& f = r.exported;
  std::string h = "<h3>Files for other programs</h3><table>";
  const auto link = [](const std::string& path) { return fmt::format("<a href=\"{0}\">{0}</a>", esc(path)); };
  h += fmt::format(
      "<tr><td class=l>{}</td><td>{}</td><td class=l>voxel fields fill, time_s, layer and "
      "density (= fill) for Blender or Houdini; lengths in mm</td></tr>",
      link(r.deposit_file), byte_size(f.deposit_bytes));
  if (!f.skin.empty())
    h += fmt::format(
        "<tr><td class=l>{}</td><td>{}</td><td class=l>as-printed skin, {} triangles, mm; a bead-by-bead STL "
        "(16 facets around each bead) would hold {} triangles ({}), {} times the skin's</td></tr>",
        link(f.skin), byte_size(f.skin_bytes), f.skin_triangles, f.bead_stl_triangles,
        byte_size(f.bead_stl_bytes), ratio_text(f));
  if (!f.fields.empty())
    h += fmt::format(
        "<tr><td class=l>{}</td><td>{}</td><td class=l>voxel fields for ParaView, {} cells "
        "(one per voxel holding material)</td></tr>",
        link(f.fields), byte_size(f.fields_bytes), f.fields_cells);
  for (const ExportedFiles::Snapshot& s : f.snapshots)
    h += fmt::format(
        "<tr><td class=l>{} {}</td><td></td><td class=l>temperatures at {:.0f} s: on the voxels (VDB) and at "
        "the thermal cells' centroids (ParaView)</td></tr>",
        link(s.vdb), link(s.vtp), s.time_s);
  return h + "</table>";
}

std::string fmt_opt(const std::optional<double>& v, const char* spec = "{:.4g}") {
  return v ? fmt::format(fmt::runtime(spec), *v) : std::string("not measured");
}

// Substrate temperatures min / mean / max, or a dash where no bead landed on anything.
std::string substrate_text(const Stats3& s) {
  return std::isfinite(s.mean) ? fmt::format("{:.1f} / {:.1f} / {:.1f}", s.min, s.mean, s.max) : "–";
}

// Healing min / mean, or a dash without interfaces.
std::string healing_text(double min, double mean) {
  return std::isfinite(min) ? fmt::format("{:.3f} / {:.3f}", min, mean) : "–";
}

// A P10-P90 band as "lo–hi" with `spec` for each end, or a dash where it was not estimated.
std::string band_text(const Band& b, const char* spec) {
  if (!std::isfinite(b.p10) || !std::isfinite(b.p90)) return "–";
  return fmt::format(fmt::runtime(spec), b.p10) + "–" + fmt::format(fmt::runtime(spec), b.p90);
}

// The verdict, and "marginal" beside it where it changes within the bands.
std::string verdict_text(const FusionRow& f) {
  return std::string(thermal::to_string(f.verdict)) + (f.marginal ? " (marginal)" : "");
}

// The table row's class: marginal before the verdict's colour.
const char* row_class(const FusionRow& f) {
  if (f.marginal) return "marginal";
  return f.verdict == thermal::Verdict::kTooHot    ? "hot"
         : f.verdict == thermal::Verdict::kTooCold ? "cold"
                                                   : "";
}

// Whether no layer time would put the layer in the window: no wait cools it enough (a least of +infinity),
// none is short enough (a most of 0), or the bounds cross.
bool no_layer_time_would(double min_s, double max_s) {
  return min_s == std::numeric_limits<double>::infinity() || max_s <= 0.0 ||
         (std::isfinite(min_s) && std::isfinite(max_s) && min_s > max_s);
}

// The layer times that would have put a layer in the window: "120 – 300", "at least 120", "at most 300",
// "none" (the bounds cross, or no wait would cool it enough), or a dash where nothing bounds them.
std::string window_range(double min_s, double max_s) {
  if (no_layer_time_would(min_s, max_s)) return "none";
  const bool lo = std::isfinite(min_s), hi = std::isfinite(max_s);
  if (lo && hi) return fmt::format("{:.0f} – {:.0f}", min_s, max_s);
  if (lo) return fmt::format("at least {:.0f}", min_s);
  if (hi) return fmt::format("at most {:.0f}", max_s);
  return "–";
}

// For the whole landing area (as the verdict counts it), and for the typical interface in brackets.
std::string window_text(const LayerRow& l) {
  return window_range(l.window_min_s, l.window_max_s) + " (" +
         window_range(l.typical_min_s, l.typical_max_s) + ")";
}

// The median over layers of the temperature up to which what lay under their beads carried them (the mean
// of each layer's, LayerRow::support_limit_c); null where no layer has one.
json median_support_limit(const VariantResult& r) {
  std::vector<double> v;
  for (const LayerRow& row : r.layers)
    if (std::isfinite(row.support_limit_c.mean)) v.push_back(row.support_limit_c.mean);
  if (v.empty()) return nullptr;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Substrate temperature at deposition per layer (least, mean, most, coloured by the layer's verdict) against
// the temperature up to which what lay under the beads carried them (per layer) and T_g.
std::string substrate_plot(const VariantResult& r) {
  if (r.layers.empty() || !r.variant) return {};
  json p = {{"kind", "substrate"},
            {"label", "substrate temperature per layer"},
            {"support", json::array()},
            {"tg", r.variant->material.glass_transition_c},
            {"hot_colour", hex(verdict_colour(thermal::Verdict::kTooHot))}};
  for (const LayerRow& row : r.layers) {
    p["layers"].push_back(row.index);
    p["min"].push_back(number_or_null(row.substrate_temp_c.min));
    p["mean"].push_back(number_or_null(row.substrate_temp_c.mean));
    p["max"].push_back(number_or_null(row.substrate_temp_c.max));
    p["support"].push_back(number_or_null(row.support_limit_c.mean));
    p["verdicts"].push_back(thermal::to_string(row.verdict));
    p["colours"].push_back(hex(verdict_colour(row.verdict)));
  }
  return plot_html(p, "the layer table below and in report.json");
}

// A layer-time window as a band for the plot: [least, most], the least 0 and the most null (the top of the
// plot) where nothing bounds them; null where no layer time would do or nothing bounds either end.
json window_band(double min_s, double max_s) {
  const bool lo = std::isfinite(min_s), hi = std::isfinite(max_s);
  if (no_layer_time_would(min_s, max_s) || (!lo && !hi)) return nullptr;
  return json::array({lo ? min_s : 0.0, hi ? json(max_s) : json(nullptr)});
}

// Each layer's time as printed against the layer times that would have put it in the fusion window, for
// all of its landing area and for half of it.
std::string layer_time_plot(const VariantResult& r) {
  if (r.layers.empty()) return {};
  json p = {{"kind", "layer_time"}, {"label", "layer time per layer against the fusion window"}};
  for (const LayerRow& row : r.layers) {
    p["layers"].push_back(row.index);
    p["duration"].push_back(number_or_null(row.duration_s));
    p["window"].push_back(window_band(row.window_min_s, row.window_max_s));
    p["typical"].push_back(window_band(row.typical_min_s, row.typical_max_s));
    p["window_text"].push_back(window_range(row.window_min_s, row.window_max_s));
    p["typical_text"].push_back(window_range(row.typical_min_s, row.typical_max_s));
    p["verdicts"].push_back(thermal::to_string(row.verdict));
    p["colours"].push_back(hex(verdict_colour(row.verdict)));
  }
  return plot_html(p, "the layer table below and in report.json");
}

// 1st, 2nd, 3rd, 4th, ..., 11th, 12th, 13th, ..., 21st.
std::string ordinal(int n) {
  const int tens = n % 100, ones = n % 10;
  const char* suffix = tens >= 11 && tens <= 13 ? "th"
                       : ones == 1              ? "st"
                       : ones == 2              ? "nd"
                       : ones == 3              ? "rd"
                                                : "th";
  return fmt::format("{}{}", n, suffix);
}

// The chosen layers' mean temperature against time, with the temperature up to which what lay under the
// beads carried them (the median layer's) and T_g.
std::string history_plot(const VariantResult& r) {
  const TemperatureHistory& hist = r.temperature_history;
  if (hist.layers.empty() || hist.times_s.size() < 2 || !r.variant) return {};
  // Minutes once the history is longer than twenty of them.
  const bool minutes = hist.times_s.back() - std::min(0.0, hist.times_s.front()) > 1200.0;
  json times = json::array();
  for (const double t : hist.times_s) times.push_back(minutes ? t / 60.0 : t);
  json p = {{"kind", "history"},
            {"label", "layer temperature against time"},
            {"times", std::move(times)},
            {"unit", minutes ? "min" : "s"},
            {"support", median_support_limit(r)},
            {"tg", r.variant->material.glass_transition_c},
            {"hot_colour", hex(verdict_colour(thermal::Verdict::kTooHot))},
            {"series", json::array()}};
  for (const LayerHistory& layer : hist.layers) {
    json temp = json::array();
    for (std::size_t i = 0; i < hist.times_s.size(); ++i)
      temp.push_back(i < layer.temp_c.size() ? number_or_null(layer.temp_c[i]) : json(nullptr));
    p["series"].push_back({{"label", fmt::format("layer {} (the {})", layer.index, ordinal(layer.index + 1))},
                           {"temp", std::move(temp)}});
  }
  return plot_html(p, "the layer table below and in report.json");
}

// What the history plot shows, for the line above it.
std::string history_caption(const VariantResult& r) {
  const double interval = r.variant ? r.variant->thermal.sample_interval_s : 0.0;
  return fmt::format(
      "<p class=muted>The mean temperature of each chosen layer's beads laid so far (volume-weighted "
      "over its thermal cells), every {:g} s. Layers are numbered from 0 at the table, as in the layer "
      "table, so layer 14 is the 15th layer printed (papers usually count from 1: their layer 15). "
      "Dashed: the substrate temperature up to which what lay under the beads carried them (the median "
      "layer's; hotter, it slumps under the next layer and the roller) and the glass transition T_g. Choose "
      "the layers with <code>output.history_layers</code>.</p>",
      interval);
}

// The part against its CAD: the deviation map with its scale, and the numbers.
std::string cad_html(const VariantResult& v) {
  const Metrics& m = v.metrics;
  if (!m.cad) return {};
  const CadMetrics& c = *m.cad;
  std::string h = "<h3>The part against its CAD</h3>";
  h += fmt::format(
      "<p class=legend>Stock the printed skin leaves over the CAD, on the picture's diverging scale (its "
      "numbers are on the picture, one scale for all variants): <span style=\"background:{}\"></span>less "
      "than requested <span style=\"background:{}\"></span>the requested {:.2f} mm <span "
      "style=\"background:{}\"></span>more</p>",
      hex(render::ColourMap::diverging().at(0.0)), hex(render::ColourMap::diverging().at(0.5)),
      c.requested_stock_mm, hex(render::ColourMap::diverging().at(1.0)));
  for (const auto& img : v.images)
    if (img.ends_with("deviation.png"))
      h += fmt::format("<p><img src=\"{}\" alt=\"{} deviation from the CAD\"></p>", esc(img), esc(v.name));
  h += "<table>";
  const auto beyond = [](bool clamped, const char* word) {
    return clamped ? fmt::format(" ({}: beyond the band)", word) : std::string();
  };
  h += table_row(
      "stock min / mean / max",
      fmt::format("{:.2f}{} / {:.2f} / {:.2f}{} mm", *m.min_stock_mm, beyond(c.min_stock_at_least, "or less"),
                  c.mean_stock_mm, c.max_stock_mm, beyond(c.max_stock_at_least, "or more")));
  h += table_row(
      "stock 5 % / 50 % / 95 % of the surface",
      fmt::format("{:.2f} / {:.2f} / {:.2f} mm", c.p05_stock_mm, c.median_stock_mm, c.p95_stock_mm));
  h += table_row("undercut (stock &lt; 0)",
                 fmt::format("{:.1f} % of {:.0f} cm²", 100 * *m.undercut_fraction, c.cad_area_mm2 / 100));
  h += table_row(fmt::format("below the requested {:.2f} mm", c.requested_stock_mm),
                 fmt::format("{:.1f} %", 100 * c.below_requested_stock_fraction));
  h += table_row("left out: on the build plate", fmt::format("{:.0f} cm²", c.plate_area_mm2 / 100));
  h += table_row(
      "skin deviation mean / rms / min / max",
      fmt::format("{:.2f} / {:.2f} / {:.2f}{} / {:.2f}{} mm", c.deviation_mean_mm, c.deviation_rms_mm,
                  c.deviation_min_mm, beyond(c.deviation_min_at_least, "or less"), c.deviation_max_mm,
                  beyond(c.deviation_max_at_least, "or more")));
  h += table_row("material outside the CAD (machined off)",
                 fmt::format("{:.0f} cm³, {:.1f} % of the deposit", c.outside_volume_mm3 / 1000,
                             100 * c.machining_waste_fraction));
  h += "</table>";
  return h;
}

// The variants side by side, each cell that differs from the baseline variant's marked with the difference
// and coloured by whether it is better or worse.
std::string variants_table(const RunResult& result) {
  const std::size_t base = result.variants.empty() ? 0 : baseline_index(result.variants);
  std::string h = "<table class=variants><tr><th class=l>variant</th><th>verdict</th>";
  for (const VariantColumn& c : variant_columns()) h += fmt::format("<th>{}</th>", c.heading);
  h += "</tr>";
  for (std::size_t i = 0; i < result.variants.size(); ++i) {
    const VariantResult& v = result.variants[i];
    h += fmt::format("<tr><td class=l>{}{}</td><td>{}</td>", esc(v.name),
                     i == base && result.variants.size() > 1 ? " <span class=muted>(baseline)</span>" : "",
                     v.passed ? "pass" : "<b>fail</b>");
    for (const VariantColumn& c : variant_columns()) {
      const VariantCell cell =
          variant_cell(c, v.metrics, i == base ? nullptr : &result.variants[base].metrics);
      if (cell.delta.empty()) {
        h += fmt::format("<td>{}</td>", cell.text);
        continue;
      }
      h += fmt::format("<td class={}>{} <span class=delta>({})</span></td>",
                       cell.judgement > 0 ? "better" : (cell.judgement < 0 ? "worse" : "diff"), cell.text,
                       cell.delta);
    }
    h += "</tr>";
  }
  h += "</table>";
  if (result.variants.size() > 1)
    h += "<p class=legend>Against the baseline: <span style=\"background:#dff2e4\"></span>better "
         "<span style=\"background:#fbe1dd\"></span>worse <span "
         "style=\"background:#fff3cc\"></span>different</p>";
  return h;
}

// The page's top: the scenario, its verdict, the variants side by side and their comparison sheets.
std::string run_html(const RunResult& result) {
  const std::string name = result.scenario ? result.scenario->name : "";
  std::string h = html_page_start("beadtwin — " + name);
  h += fmt::format("<h1>{}</h1>", esc(name));
  if (result.scenario && !result.scenario->description.empty())
    h += fmt::format("<p class=\"muted\">{}</p>", esc(result.scenario->description));
  h += fmt::format("<p><span class=\"verdict {}\">{}</span> beadtwin {} · {} variant(s) · {:.1f} s</p>",
                   result.passed ? "pass" : "fail", result.passed ? "PASSED" : "FAILED", BEADTWIN_VERSION,
                   result.variants.size(), result.wall_time_s);
  h += "<h2>Variants</h2>" + variants_table(result);
  if (!result.sheets.empty()) {
    h += "<h2>The variants side by side</h2><p class=legend>Each picture of every variant, from one camera "
         "on one colour scale.</p>";
    for (const auto& sheet : result.sheets)
      h += fmt::format("<p><img src=\"{}\" alt=\"{}\"></p>", esc(sheet), esc(sheet));
  }
  return h;
}

// What the stages chose for the user, and the gates with their values.
std::string notes_and_gates_html(const VariantResult& v) {
  std::string h;
  if (!v.notes.empty()) {
    h += "<h3>Notes</h3><ul>";
    for (const std::string& n : v.notes) h += "<li>" + esc(n) + "</li>";
    h += "</ul>";
  }
  if (v.gates.empty())
    return h + "<h3>Gates</h3><p class=muted>No gates: the variant passes as long as it runs.</p>";
  h += "<h3>Gates</h3><table><tr><th class=l>gate</th><th>value</th><th>result</th></tr>";
  for (const auto& g : v.gates)
    h += fmt::format("<tr><td class=l><code>{}</code></td><td>{}</td><td>{}</td></tr>", esc(g.expr),
                     fmt_opt(g.value), g.passed ? "pass" : "<b>fail</b>");
  return h + "</table>";
}

// The pictures (each with its own title, legend and scale), with what the fusion colours mean; the
// sections' picture and the deviation map come with their own headings.
std::string pictures_html(const VariantResult& v) {
  std::string h;
  const bool fusion = std::any_of(v.images.begin(), v.images.end(), [](const std::string& img) {
    return std::filesystem::path(img).stem().string().starts_with("fusion");
  });
  if (!v.images.empty()) h += "<h3>Pictures</h3>";
  if (fusion)
    h += fmt::format(
        "<p class=legend>Fusion: each piece of bead by its worst interface where it landed: <span "
        "style=\"background:{}\"></span>fuses <span style=\"background:{}\"></span>too hot (the soft "
        "material "
        "under it slumps under the bead and the roller) <span style=\"background:{}\"></span>too cold (an "
        "interface "
        "that "
        "does not heal) <span style=\"background:{}\"></span>marginal (the verdict changes within the "
        "P10-P90 band of the inputs' plausible values) <span style=\"background:{}\"></span>no interface "
        "(on the table alone)</p>",
        hex(verdict_colour(thermal::Verdict::kOk)), hex(verdict_colour(thermal::Verdict::kTooHot)),
        hex(verdict_colour(thermal::Verdict::kTooCold)), hex(verdict_colour(thermal::Verdict::kMarginal)),
        hex(verdict_colour(thermal::Verdict::kNoInterface)));
  for (const auto& img : v.images) {
    if (img.ends_with("sections.png") || img.ends_with("deviation.png")) continue;
    h += fmt::format("<p><img src=\"{}\" alt=\"{} {}\"></p>", esc(img), esc(v.name), esc(img));
  }
  return h;
}

// The sections by colour, with their boundary passes and fill, over the sections' picture.
std::string sections_legend_html(const VariantResult& v) {
  if (!v.variant || v.variant->sections.empty()) return {};
  std::string h = "<h3>The sections</h3><p class=legend>";
  for (std::size_t i = 0; i < v.variant->sections.size(); ++i) {
    const auto& sec = v.variant->sections[i];
    h += fmt::format("<span style=\"background:{}\"></span>{} ({} boundary pass{}, fill {}) ",
                     hex(section_colour(static_cast<int>(i))), esc(sec.name), sec.boundary.passes,
                     sec.boundary.passes == 1 ? "" : "es", sec.fill.enabled ? "on" : "off");
  }
  h += "</p>";
  for (const auto& img : v.images)
    if (img.ends_with("sections.png"))
      h += fmt::format("<p><img src=\"{}\" alt=\"{} sections\"></p>", esc(img), esc(v.name));
  return h;
}

// The plots against layers and time, each under its heading.
std::string plots_html(const VariantResult& v) {
  std::string h = "<h3>Substrate temperature when each layer lands</h3>" + substrate_plot(v);
  h += "<h3>Layer time against the fusion window</h3><p class=muted>Each layer's time as printed, coloured "
       "by "
       "its verdict, and in green the layer times that would have put it in the fusion window: long "
       "enough for what lies under the beads to carry them, short enough for it to stay warm "
       "enough to heal; darker for all of the layer's landing area (as its verdict counts it), lighter for "
       "half of it (the typical interface). A first-order estimate from the cooling each interface was on "
       "as it was covered: "
       "it says which way to move and about how far.</p>" +
       layer_time_plot(v);
  if (const std::string plot = history_plot(v); !plot.empty())
    h += "<h3>Temperature of chosen layers against time</h3>" + history_caption(v) + plot;
  return h;
}

// The variant's headline figures, written for people (report.json has every metric as measured).
std::string metrics_table_html(const Metrics& m) {
  std::string h = "<h3>Metrics</h3><table>";
  h += table_row("print time", hms(m.print_time_s));
  h += table_row("print length", fmt::format("{:.1f} m", m.print_length_mm / 1000));
  h += table_row("travel length", fmt::format("{:.1f} m", m.travel_length_mm / 1000));
  h += table_row("commanded volume", fmt::format("{:.0f} cm³", m.commanded_volume_mm3 / 1000));
  h += table_row("deposited volume", fmt::format("{:.0f} cm³", m.deposited_volume_mm3 / 1000));
  h += table_row("swept bead volume (before conservation)",
                 fmt::format("{:.0f} cm³", m.swept_volume_mm3 / 1000));
  h += table_row("mass", fmt::format("{:.2f} kg", m.mass_kg));
  h += table_row("material cost", fmt::format("{:.2f}", m.material_cost));
  h += table_row("porosity", fmt::format("{:.2f} %", 100 * m.porosity));
  h += table_row("extruder demand (of its limit)",
                 fmt::format("{:.0f} %{}", 100 * m.extruder_demand,
                             m.extruder_demand > 1 ? " — more than it gives" : ""));
  h += table_row("voids found by the slicer",
                 fmt::format("{} ({:.0f} mm²)", m.planned_voids, m.planned_void_area_mm2));
  h += table_row("voids (deposit)", fmt::format("{} ({:.0f} cm³)", m.voids, m.void_volume_mm3 / 1000));
  h += table_row("ploughed by the roller", fmt::format("{:.1f} cm³", m.plough_volume_mm3 / 1000));
  h += table_row("bead laid over nothing", fmt::format("{:.0f} mm", m.unsupported_length_mm));
  h += table_row("corners too tight for the roller", fmt::format("{}", m.roller_corners));
  h += table_row("collisions", fmt::format("{}", m.collisions));
  if (m.min_layer_fill)
    h += table_row("layer fill (material / outline × height)",
                   fmt::format("{:.3f} .. {:.3f}", *m.min_layer_fill, m.max_layer_fill.value_or(0)));
  h += table_row("min stock", m.cad && m.cad->min_stock_at_least
                                  ? "at most " + fmt_opt(m.min_stock_mm, "{:.2f} mm")
                                  : fmt_opt(m.min_stock_mm, "{:.2f} mm"));
  h += table_row(
      "undercut (share of the CAD surface the print falls short of)",
      m.undercut_fraction ? fmt::format("{:.1f} %", 100 * *m.undercut_fraction) : fmt_opt(std::nullopt));
  h += table_row("voxels", fmt::format("{} at {:.2f} mm", m.voxels, m.voxel_size_mm));
  h += table_row("thermal energy balance error", fmt::format("{:.1e}", m.thermal_energy_error));
  return h + "</table>";
}

std::string sections_table_html(const std::vector<SectionRow>& sections) {
  std::string h =
      "<h3>Sections</h3><table><tr><th class=l>section</th><th>layers</th><th>print time</th><th>mean "
      "layer time s</th><th>bead m</th><th>material kg</th><th>cost</th><th>interfaces</th><th>substrate "
      "°C "
      "at deposition min/mean/max</th><th>too hot %</th><th>too cold %</th><th>healing min/mean</th>"
      "<th>healing P10–P90</th><th>marginal %</th><th class=l>verdict</th></tr>";
  for (const SectionRow& sr : sections) {
    const Stats3& s = sr.substrate_temp_c;
    h += fmt::format(
        "<tr class=\"{}\"><td class=l>{}</td><td>{}</td><td>{}</td><td>{:.0f}</td><td>{:.1f}</td>"
        "<td>{:.2f}</td><td>{:.2f}</td><td>{}</td><td>{}</td><td>{:.1f}</td><td>{:.1f}</td><td>{}</td>"
        "<td>{}</td><td>{:.1f}</td><td class=l>{}</td></tr>",
        row_class(sr), esc(sr.name), sr.layers, hms(sr.print_time_s), sr.mean_layer_time_s,
        sr.print_length_mm / 1000, sr.mass_kg, sr.material_cost, sr.interfaces, substrate_text(s),
        100 * sr.too_hot_fraction, 100 * sr.too_cold_fraction, healing_text(sr.healing, sr.healing_mean),
        band_text(sr.healing_band, "{:.3f}"), 100 * sr.marginal_fraction, verdict_text(sr));
  }
  return h + "</table>";
}

std::string layers_table_html(const std::vector<LayerRow>& layers) {
  std::string h =
      "<details open><summary>Layers</summary><table><tr><th>layer</th><th>z mm</th><th "
      "class=l>section</th><th>start s</th>"
      "<th>duration s</th><th>substrate °C at deposition min/mean/max</th><th>substrate °C P10–P90</th>"
      "<th>interfaces</th><th>too hot %</th><th>too cold %</th><th>healing min/mean</th>"
      "<th>healing P10–P90</th><th>marginal %</th><th class=l>verdict</th>"
      "<th>layer time for the window s (typical)</th></tr>";
  for (const auto& l : layers) {
    const Stats3& s = l.substrate_temp_c;
    h += fmt::format(
        "<tr class=\"{}\"><td>{}</td><td>{:.1f}</td><td class=l>{}</td><td>{:.0f}</td><td>{:.1f}</td>"
        "<td>{}</td><td>{}</td><td>{}</td><td>{:.1f}</td><td>{:.1f}</td><td>{}</td><td>{}</td><td>{:.1f}</td>"
        "<td class=l>{}</td><td>{}</td></tr>",
        row_class(l), l.index, l.z_mm, esc(l.section), l.start_s, l.duration_s, substrate_text(s),
        band_text(l.substrate_band_c, "{:.1f}"), l.interfaces, 100 * l.too_hot_fraction,
        100 * l.too_cold_fraction, healing_text(l.healing, l.healing_mean),
        band_text(l.healing_band, "{:.3f}"), 100 * l.marginal_fraction, verdict_text(l), window_text(l));
  }
  return h + "</table></details>";
}

std::string stage_times_html(const VariantResult& v) {
  std::string h = "<details><summary>Time per stage</summary><table>";
  for (const auto& s : v.stage_times) h += table_row(s.name, fmt::format("{:.2f} s", s.seconds));
  h += table_row("all, wall clock",
                 fmt::format("{:.2f} s (the CAD comparison runs beside the thermal stage)", v.wall_time_s));
  return h + "</table></details>";
}

// One variant's part of the page.
std::string variant_html(const VariantResult& v) {
  std::string h = fmt::format("<h2>Variant {}</h2>", esc(v.name));
  h += notes_and_gates_html(v);
  h += pictures_html(v);
  h += sections_legend_html(v);
  h += cad_html(v);
  h += plots_html(v);
  h += metrics_table_html(v.metrics);
  h += fmt::format("<p>Print program: <a href=\"{0}\">{0}</a></p>", esc(v.program));
  h += files_html(v);
  h += sections_table_html(v.metrics.sections);
  h += layers_table_html(v.layers);
  h += defects_html(v.defects);
  return h + stage_times_html(v);
}

}  // namespace

std::string report_html(const RunResult& result) {
  std::string h = run_html(result);
  for (const VariantResult& v : result.variants) h += variant_html(v);
  return h + html_page_end();
}

}  // namespace beadtwin::scenarios
