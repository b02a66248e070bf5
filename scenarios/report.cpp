#include "scenarios/report.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.hpp"
#include "render/colormap.hpp"
#include "scenarios/colours.hpp"
#include "scenarios/report_parameters.hpp"
#include "scenarios/report_scripts.hpp"
#include "scenarios/report_text.hpp"
#include "scenarios/run.hpp"

namespace beadtwin::scenarios {
namespace {

// Defects listed by position: in report.json, and in the html (report.json has the rest).
constexpr std::size_t kDefectsInJson = 1000;
constexpr std::size_t kDefectsInHtml = 20;

using nlohmann::json;

json number_or_null(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}
json optional_json(const std::optional<double>& v) {
  return v ? number_or_null(*v) : json(nullptr);
}
json stats_json(const Stats3& s) {
  return {{"min", number_or_null(s.min)}, {"mean", number_or_null(s.mean)}, {"max", number_or_null(s.max)}};
}

// Polygons as [[[x, y], ...], ...] in mm.
// The rest of the part-versus-CAD comparison, or null without a CAD.
json cad_json(const Metrics& m) {
  if (!m.cad) return nullptr;
  const CadMetrics& c = *m.cad;
  return {{"max_stock_mm", number_or_null(c.max_stock_mm)},
          {"mean_stock_mm", number_or_null(c.mean_stock_mm)},
          {"stock_percentiles_mm",
           {{"p05", number_or_null(c.p05_stock_mm)},
            {"p50", number_or_null(c.median_stock_mm)},
            {"p95", number_or_null(c.p95_stock_mm)}}},
          {"min_stock_at_least", c.min_stock_at_least},
          {"max_stock_at_least", c.max_stock_at_least},
          {"requested_stock_mm", number_or_null(c.requested_stock_mm)},
          {"below_requested_stock_fraction", number_or_null(c.below_requested_stock_fraction)},
          {"cad_area_mm2", number_or_null(c.cad_area_mm2)},
          {"plate_area_mm2", number_or_null(c.plate_area_mm2)},
          {"deviation_mm",
           {{"mean", number_or_null(c.deviation_mean_mm)},
            {"rms", number_or_null(c.deviation_rms_mm)},
            {"min", number_or_null(c.deviation_min_mm)},
            {"max", number_or_null(c.deviation_max_mm)},
            {"min_at_least", c.deviation_min_at_least},
            {"max_at_least", c.deviation_max_at_least}}},
          {"outside_volume_mm3", number_or_null(c.outside_volume_mm3)},
          {"machining_waste_fraction", number_or_null(c.machining_waste_fraction)},
          {"band_mm", number_or_null(c.band_mm)},
          {"deviation_map",
           {{"white_at_mm", number_or_null(c.requested_stock_mm)},
            {"blue_at_mm", number_or_null(c.requested_stock_mm - c.map_half_range_mm)},
            {"red_at_mm", number_or_null(c.requested_stock_mm + c.map_half_range_mm)}}}};
}

// The files for other programs, with their sizes; a file not written is null.
json files_json(const VariantResult& r) {
  const ExportedFiles& f = r.exported;
  json skin = nullptr, fields = nullptr;
  if (!f.skin.empty())
    skin = {{"path", f.skin},
            {"bytes", f.skin_bytes},
            {"triangles", f.skin_triangles},
            {"bead_by_bead_stl", {{"triangles", f.bead_stl_triangles}, {"bytes", f.bead_stl_bytes}}},
            {"bead_by_bead_triangles_over_skin",
             f.skin_triangles > 0
                 ? json(static_cast<double>(f.bead_stl_triangles) / static_cast<double>(f.skin_triangles))
                 : json(nullptr)}};
  if (!f.fields.empty()) fields = {{"path", f.fields}, {"bytes", f.fields_bytes}, {"cells", f.fields_cells}};
  json snapshots = json::array();
  for (const ExportedFiles::Snapshot& s : f.snapshots)
    snapshots.push_back({{"time_s", s.time_s}, {"vdb", s.vdb}, {"vtp", s.vtp}});
  return {{"deposit", {{"path", r.deposit_file}, {"bytes", f.deposit_bytes}}},
          {"skin", skin},
          {"fields", fields},
          {"temperature_snapshots", snapshots}};
}

// Rounded for the file: a hundredth of a kelvin and of a second is far below what the model resolves, and
// keeps a float's tail of digits out of report.json.
json rounded(double v) {
  return std::isfinite(v) ? json(std::round(v * 100.0) / 100.0) : json(nullptr);
}

json history_json(const TemperatureHistory& h) {
  json times = json::array();
  for (const double t : h.times_s) times.push_back(rounded(t));
  json layers = json::array();
  for (const LayerHistory& l : h.layers) {
    json temps = json::array();
    for (const float temp : l.temp_c) temps.push_back(rounded(temp));
    layers.push_back({{"index", l.index}, {"temp_c", std::move(temps)}});
  }
  return {{"times_s", std::move(times)}, {"layers", std::move(layers)}};
}

// The numbers of a layer's or a section's interfaces.
json fusion_json(const FusionRow& f) {
  return {{"substrate_temp_c", stats_json(f.substrate_temp_c)},
          {"interfaces", f.interfaces},
          {"healing_min", number_or_null(f.healing)},
          {"healing_mean", number_or_null(f.healing_mean)},
          {"too_hot", f.too_hot},
          {"too_cold", f.too_cold},
          {"too_hot_fraction", f.too_hot_fraction},
          {"too_cold_fraction", f.too_cold_fraction},
          {"verdict", thermal::to_string(f.verdict)}};
}

json variant_json(const VariantResult& r) {
  const Metrics& m = r.metrics;
  json gates = json::array();
  for (const auto& g : r.gates) {
    json gate = {{"name", g.name},
                 {"expr", g.expr},
                 {"value", optional_json(g.value)},
                 {"passed", g.passed},
                 {"message", g.message}};
    if (g.threshold) gate["threshold"] = *g.threshold;  // a relative gate's, from the baseline
    gates.push_back(gate);
  }
  json layers = json::array();
  for (const auto& l : r.layers) {
    json row = fusion_json(l);
    row.update({{"index", l.index},
                {"z_mm", l.z_mm},
                {"section", l.section},
                {"start_s", l.start_s},
                {"duration_s", l.duration_s},
                {"layer_time_window_s",
                 {{"min", number_or_null(l.window_min_s)},
                  {"max", number_or_null(l.window_max_s)},
                  {"typical_min", number_or_null(l.typical_min_s)},
                  {"typical_max", number_or_null(l.typical_max_s)}}},
                {"fill_ratio", l.fill_ratio > 0 ? json(l.fill_ratio) : json(nullptr)},
                {"bead_height_mm", l.bead_height_mm},
                {"void_mm3", l.void_mm3},
                {"plough_mm3", l.plough_mm3},
                {"unsupported_mm", l.unsupported_mm}});
    layers.push_back(row);
  }
  json sections = json::array();
  for (const SectionRow& s : r.metrics.sections) {
    json row = fusion_json(s);
    row["name"] = s.name;
    row["layers"] = s.layers;
    row["print_time_s"] = s.print_time_s;
    row["print_length_mm"] = s.print_length_mm;
    row["commanded_volume_mm3"] = s.commanded_volume_mm3;
    row["mass_kg"] = s.mass_kg;
    row["material_cost"] = s.material_cost;
    row["mean_layer_time_s"] = s.mean_layer_time_s;
    sections.push_back(row);
  }
  json defects = json::array();
  for (std::size_t i = 0; i < std::min(r.defects.size(), kDefectsInJson); ++i) {
    const sim::Defect& d = r.defects[i];
    defects.push_back({{"kind", sim::to_string(d.kind)},
                       {"position_mm", {d.position_mm.x(), d.position_mm.y(), d.position_mm.z()}},
                       {"layer", d.layer},
                       {"move", d.move},
                       {"source_line", d.source_line > 0 ? json(d.source_line) : json(nullptr)},
                       {"size", d.size},
                       {"detail", d.detail}});
  }
  json stages = json::object();
  for (const auto& s : r.stage_times) stages[s.name] = s.seconds;
  return {
      {"name", r.name},
      {"passed", r.passed},
      {"gates", gates},
      {"values", m.values()},  // every gate metric measured, by its name: what a sweep gathers
      {"metrics",
       {{"layers", m.layers},
        {"print_time_s", m.print_time_s},
        {"print_length_mm", m.print_length_mm},
        {"travel_length_mm", m.travel_length_mm},
        {"commanded_volume_mm3", m.commanded_volume_mm3},
        {"deposited_volume_mm3", m.deposited_volume_mm3},
        {"mass_kg", m.mass_kg},
        {"material_cost", m.material_cost},
        {"porosity", m.porosity},
        {"min_stock_mm", optional_json(m.min_stock_mm)},
        {"undercut_fraction", optional_json(m.undercut_fraction)},
        {"max_stock_mm", optional_json(m.get("max_stock_mm"))},
        {"mean_stock_mm", optional_json(m.get("mean_stock_mm"))},
        {"below_requested_stock_fraction", optional_json(m.get("below_requested_stock_fraction"))},
        {"deviation_rms_mm", optional_json(m.get("deviation_rms_mm"))},
        {"machining_waste_fraction", optional_json(m.get("machining_waste_fraction"))},
        {"cad", cad_json(m)},
        {"interfaces",
         {{"count", m.interfaces},
          {"too_hot_fraction", m.too_hot_fraction},
          {"too_cold_fraction", m.too_cold_fraction},
          {"min_healing", optional_json(m.get("interfaces.min_healing"))},
          {"mean_healing", optional_json(m.get("interfaces.mean_healing"))}}},
        {"layer_time_s", stats_json(m.layer_time_s)},
        {"planned_voids", m.planned_voids},
        {"extruder_demand", m.extruder_demand},
        {"planned_void_area_mm2", m.planned_void_area_mm2},
        {"defects",
         {{"voids", m.voids},
          {"void_volume_mm3", m.void_volume_mm3},
          {"plough_volume_mm3", m.plough_volume_mm3},
          {"unsupported_length_mm", m.unsupported_length_mm},
          {"roller_corners", m.roller_corners},
          {"collisions", m.collisions}}},
        {"layer_fill", {{"min", optional_json(m.min_layer_fill)}, {"max", optional_json(m.max_layer_fill)}}},
        {"deposit",
         {{"voxel_size_mm", m.voxel_size_mm},
          {"voxels", m.voxels},
          {"swept_volume_mm3", m.swept_volume_mm3},
          {"redistributed_volume_mm3", m.redistributed_volume_mm3}}},
        {"thermal",
         {{"energy_balance_rel_error", m.thermal_energy_error}, {"cvode_steps", m.thermal_steps}}}}},
      {"layers", layers},
      {"sections", sections},
      {"temperature_history", history_json(r.temperature_history)},
      {"defects", defects},
      {"notes", r.notes},
      {"images", r.images},
      {"images_exr", r.exr_images},
      {"progress_frames", r.progress_frames},
      {"program", r.program},
      {"deposit", r.deposit_file},
      {"files", files_json(r)},
      {"stage_seconds", stages},
      {"parameters", r.variant ? parameters_json(*r.variant) : json(nullptr)}};
}

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

namespace {

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

std::string hms(double s) {
  const long t = std::lround(s);
  return fmt::format("{}:{:02}:{:02}", t / 3600, (t / 60) % 60, t % 60);
}

// Substrate temperatures min / mean / max, or a dash where no bead landed on anything.
std::string substrate_text(const Stats3& s) {
  return std::isfinite(s.mean) ? fmt::format("{:.1f} / {:.1f} / {:.1f}", s.min, s.mean, s.max) : "–";
}

// Healing min / mean, or a dash without interfaces.
std::string healing_text(double min, double mean) {
  return std::isfinite(min) ? fmt::format("{:.3f} / {:.3f}", min, mean) : "–";
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

// A number for a plot's data: null where it is not finite (a layer with nothing to measure).
json finite_or_null(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

}  // namespace

std::string plot_html(const json& spec, std::string_view where_else) {
  std::string text = spec.dump();
  std::string safe;
  safe.reserve(text.size());
  for (const char c : text) safe += c == '<' ? std::string("\\u003c") : std::string(1, c);
  return "<script type=\"application/json\" class=\"beadtwin-plot\">" + safe +
         "</script><noscript><p class=muted>This plot is drawn by a script; the same numbers are in " +
         esc(where_else) + ".</p></noscript>";
}

namespace {

// Substrate temperature at deposition per layer (least, mean, most, coloured by the layer's verdict) against
// the support limit and T_g.
std::string substrate_plot(const VariantResult& r) {
  if (r.layers.empty() || !r.variant) return {};
  json p = {{"kind", "substrate"},
            {"label", "substrate temperature per layer"},
            {"support", r.variant->material.support_limit_c},
            {"tg", r.variant->material.glass_transition_c},
            {"hot_colour", hex(verdict_colour(thermal::Verdict::kTooHot))}};
  for (const LayerRow& row : r.layers) {
    p["layers"].push_back(row.index);
    p["min"].push_back(finite_or_null(row.substrate_temp_c.min));
    p["mean"].push_back(finite_or_null(row.substrate_temp_c.mean));
    p["max"].push_back(finite_or_null(row.substrate_temp_c.max));
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
    p["duration"].push_back(finite_or_null(row.duration_s));
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

// The chosen layers' mean temperature against time, with the support limit and T_g.
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
            {"support", r.variant->material.support_limit_c},
            {"tg", r.variant->material.glass_transition_c},
            {"hot_colour", hex(verdict_colour(thermal::Verdict::kTooHot))},
            {"series", json::array()}};
  for (const LayerHistory& layer : hist.layers) {
    json temp = json::array();
    for (std::size_t i = 0; i < hist.times_s.size(); ++i)
      temp.push_back(i < layer.temp_c.size() ? finite_or_null(layer.temp_c[i]) : json(nullptr));
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
      "Dashed: the support limit (a substrate above it is too soft to carry the next layer) and the "
      "glass transition T_g. Choose the layers with <code>output.history_layers</code>.</p>",
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
  const auto row = [&h](std::string_view k, const std::string& val) {
    h += fmt::format("<tr><td class=l>{}</td><td>{}</td></tr>", k, val);
  };
  const auto beyond = [](bool clamped, const char* word) {
    return clamped ? fmt::format(" ({}: beyond the band)", word) : std::string();
  };
  row("stock min / mean / max",
      fmt::format("{:.2f}{} / {:.2f} / {:.2f}{} mm", *m.min_stock_mm, beyond(c.min_stock_at_least, "or less"),
                  c.mean_stock_mm, c.max_stock_mm, beyond(c.max_stock_at_least, "or more")));
  row("stock 5 % / 50 % / 95 % of the surface",
      fmt::format("{:.2f} / {:.2f} / {:.2f} mm", c.p05_stock_mm, c.median_stock_mm, c.p95_stock_mm));
  row("undercut (stock &lt; 0)",
      fmt::format("{:.1f} % of {:.0f} cm²", 100 * *m.undercut_fraction, c.cad_area_mm2 / 100));
  row(fmt::format("below the requested {:.2f} mm", c.requested_stock_mm),
      fmt::format("{:.1f} %", 100 * c.below_requested_stock_fraction));
  row("left out: on the build plate", fmt::format("{:.0f} cm²", c.plate_area_mm2 / 100));
  row("skin deviation mean / rms / min / max",
      fmt::format("{:.2f} / {:.2f} / {:.2f}{} / {:.2f}{} mm", c.deviation_mean_mm, c.deviation_rms_mm,
                  c.deviation_min_mm, beyond(c.deviation_min_at_least, "or less"), c.deviation_max_mm,
                  beyond(c.deviation_max_at_least, "or more")));
  row("material outside the CAD (machined off)",
      fmt::format("{:.0f} cm³, {:.1f} % of the deposit", c.outside_volume_mm3 / 1000,
                  100 * c.machining_waste_fraction));
  h += "</table>";
  return h;
}

}  // namespace

std::string report_json(const RunResult& result) {
  json j;
  j["tool"] = "beadtwin";
  j["version"] = BEADTWIN_VERSION;
  j["scenario"] = result.scenario ? result.scenario->name : "";
  j["scenario_file"] = result.scenario ? result.scenario->file : "";
  j["passed"] = result.passed;
  j["wall_time_s"] = result.wall_time_s;
  j["warnings"] = result.scenario ? result.scenario->warnings : std::vector<std::string>{};
  j["variants"] = json::array();
  for (const auto& v : result.variants) j["variants"].push_back(variant_json(v));
  j["sheets"] = result.sheets;
  return j.dump(2) + "\n";
}

// One column of the variants table: its heading, the value, how it is written, and which way is better
// (-1 lower, +1 higher, 0 neither), so a difference from the baseline can be marked better or worse.
struct VariantColumn {
  const char* heading;
  std::function<std::optional<double>(const Metrics&)> value;
  std::function<std::string(double)> text;
  int better = 0;
  bool fraction = false;   // differences in points rather than per cent
  bool in_summary = true;  // also in summary.md, which stays short enough for a pull-request comment
};

const std::vector<VariantColumn>& variant_columns() {
  static const auto percent = [](double v) { return fmt::format("{:.1f} %", 100 * v); };
  static const std::vector<VariantColumn> columns = {
      {"layers", [](const Metrics& m) { return std::optional<double>(m.layers); },
       [](double v) { return fmt::format("{:.0f}", v); }, 0, false, false},
      {"print time", [](const Metrics& m) { return std::optional<double>(m.print_time_s); },
       [](double v) { return hms(v); }, -1},
      {"mass kg", [](const Metrics& m) { return std::optional<double>(m.mass_kg); },
       // A tenth of a kilogram at LSAM scale, three digits for a desktop part's grams.
       [](double v) { return v >= 1.0 ? fmt::format("{:.1f}", v) : fmt::format("{:.3g}", v); }, -1},
      {"porosity", [](const Metrics& m) { return std::optional<double>(m.porosity); },
       [](double v) { return fmt::format("{:.2f} %", 100 * v); }, -1, true},
      {"too hot", [](const Metrics& m) { return std::optional<double>(m.too_hot_fraction); }, percent, -1,
       true},
      {"too cold", [](const Metrics& m) { return std::optional<double>(m.too_cold_fraction); }, percent, -1,
       true},
      {"min healing",
       [](const Metrics& m) {
         return m.interfaces > 0 ? std::optional<double>(m.min_healing) : std::nullopt;
       },
       [](double v) { return fmt::format("{:.3f}", v); }, +1},
      {"mean layer time s", [](const Metrics& m) { return std::optional<double>(m.layer_time_s.mean); },
       [](double v) { return fmt::format("{:.0f}", v); }, 0, false, false},
      {"min stock mm", [](const Metrics& m) { return m.min_stock_mm; },
       [](double v) { return fmt::format("{:.2f}", v); }, +1},
  };
  return columns;
}

// A cell of the variants table: the value as written, and its difference from the baseline's where it
// differs (in points for fractions, else per cent), with -1 worse, +1 better, 0 neither.
struct VariantCell {
  std::string text;   // "—" without a value
  std::string delta;  // "+1.5 %", "-2.0 pt"; empty where it does not differ or for the baseline itself
  int judgement = 0;
};

VariantCell variant_cell(const VariantColumn& c, const Metrics& m, const Metrics* baseline) {
  const std::optional<double> value = c.value(m);
  if (!value || !std::isfinite(*value)) return {"—", {}, 0};
  VariantCell cell{c.text(*value), {}, 0};
  const std::optional<double> was = baseline ? c.value(*baseline) : std::nullopt;
  if (!was || !std::isfinite(*was)) return cell;
  const double change = *value - *was;
  const double scale = std::max(std::abs(*was), 1e-12);
  const bool differs = c.fraction ? std::abs(change) >= 5e-4 : std::abs(change) / scale >= 0.005;
  if (!differs) return cell;
  cell.delta =
      c.fraction ? fmt::format("{:+.1f} pt", 100 * change) : fmt::format("{:+.1f} %", 100 * change / scale);
  cell.judgement = change * c.better > 0 ? +1 : (c.better == 0 ? 0 : -1);
  return cell;
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

std::string_view report_style() {
  return R"(<style>
body{font-family:system-ui,sans-serif;margin:2em auto;max-width:1100px;color:#222;padding:0 1em}
h1{margin-bottom:.2em} .verdict{display:inline-block;padding:.2em .7em;border-radius:4px;color:#fff;font-weight:600}
.pass{background:#2e8b57}.fail{background:#c0392b} table{border-collapse:collapse;margin:1em 0;font-size:13px}
td,th{border:1px solid #ddd;padding:3px 8px;text-align:right} th{background:#f4f5f7} td.l,th.l{text-align:left}
tr.hot td{background:#fde2df} tr.cold td{background:#dfe8f8} img{max-width:100%;border:1px solid #ddd}
.legend span{display:inline-block;width:12px;height:12px;margin:0 4px 0 12px;vertical-align:middle}
details{margin:1em 0} .muted{color:#777} .plot{position:relative;height:300px;margin:1em 0}
td.better{background:#dff2e4} td.worse{background:#fbe1dd} td.diff{background:#fff3cc} .delta{color:#555;font-size:11px}
</style>
)";
}

std::string report_html(const RunResult& result) {
  const std::string name = result.scenario ? result.scenario->name : "";
  std::string h;
  h += "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">";
  h += fmt::format("<title>beadtwin — {}</title>", esc(name));
  h += report_style();
  h += "</head><body>\n";
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
  for (const auto& v : result.variants) {
    h += fmt::format("<h2>Variant {}</h2>", esc(v.name));
    if (!v.notes.empty()) {
      h += "<h3>Notes</h3><ul>";
      for (const std::string& n : v.notes) h += "<li>" + esc(n) + "</li>";
      h += "</ul>";
    }
    if (v.gates.empty()) {
      h += "<h3>Gates</h3><p class=muted>No gates: the variant passes as long as it runs.</p>";
    } else {
      h += "<h3>Gates</h3><table><tr><th class=l>gate</th><th>value</th><th>result</th></tr>";
      for (const auto& g : v.gates)
        h += fmt::format("<tr><td class=l><code>{}</code></td><td>{}</td><td>{}</td></tr>", esc(g.expr),
                         fmt_opt(g.value), g.passed ? "pass" : "<b>fail</b>");
      h += "</table>";
    }
    // The pictures (each with its own title, legend and scale), and what the fusion colours mean.
    const bool fusion = std::any_of(v.images.begin(), v.images.end(), [](const std::string& img) {
      return std::filesystem::path(img).stem().string().starts_with("fusion");
    });
    if (!v.images.empty()) h += "<h3>Pictures</h3>";
    if (fusion)
      h += fmt::format(
          "<p class=legend>Fusion: each piece of bead by its worst interface where it landed: <span "
          "style=\"background:{}\"></span>fuses <span style=\"background:{}\"></span>too hot (the substrate "
          "under it above the support limit) <span style=\"background:{}\"></span>too cold (an interface "
          "that "
          "does not heal) <span style=\"background:{}\"></span>no interface (on the table alone)</p>",
          hex(verdict_colour(thermal::Verdict::kOk)), hex(verdict_colour(thermal::Verdict::kTooHot)),
          hex(verdict_colour(thermal::Verdict::kTooCold)),
          hex(verdict_colour(thermal::Verdict::kNoInterface)));
    for (const auto& img : v.images) {
      if (img.ends_with("sections.png") || img.ends_with("deviation.png")) continue;
      h += fmt::format("<p><img src=\"{}\" alt=\"{} {}\"></p>", esc(img), esc(v.name), esc(img));
    }
    if (v.variant && !v.variant->sections.empty()) {
      h += "<h3>The sections</h3><p class=legend>";
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
    }
    h += cad_html(v);
    h += "<h3>Substrate temperature when each layer lands</h3>" + substrate_plot(v);
    h += "<h3>Layer time against the fusion window</h3><p class=muted>Each layer's time as printed, coloured "
         "by "
         "its verdict, and in green the layer times that would have put it in the fusion window: long "
         "enough for the layer below to cool under the support limit, short enough for it to stay warm "
         "enough to heal; darker for all of the layer's landing area (as its verdict counts it), lighter for "
         "half of it (the typical interface). A first-order estimate from the cooling each interface was on "
         "as it was covered: "
         "it says which way to move and about how far.</p>" +
         layer_time_plot(v);
    if (const std::string plot = history_plot(v); !plot.empty())
      h += "<h3>Temperature of chosen layers against time</h3>" + history_caption(v) + plot;
    const Metrics& m = v.metrics;
    h += "<h3>Metrics</h3><table>";
    auto row = [&h](std::string_view k, const std::string& val) {
      h += fmt::format("<tr><td class=l>{}</td><td>{}</td></tr>", k, val);
    };
    row("print time", hms(m.print_time_s));
    row("print length", fmt::format("{:.1f} m", m.print_length_mm / 1000));
    row("travel length", fmt::format("{:.1f} m", m.travel_length_mm / 1000));
    row("commanded volume", fmt::format("{:.0f} cm³", m.commanded_volume_mm3 / 1000));
    row("deposited volume", fmt::format("{:.0f} cm³", m.deposited_volume_mm3 / 1000));
    row("swept bead volume (before conservation)", fmt::format("{:.0f} cm³", m.swept_volume_mm3 / 1000));
    row("mass", fmt::format("{:.2f} kg", m.mass_kg));
    row("material cost", fmt::format("{:.2f}", m.material_cost));
    row("porosity", fmt::format("{:.2f} %", 100 * m.porosity));
    row("extruder demand (of its limit)", fmt::format("{:.0f} %{}", 100 * m.extruder_demand,
                                                      m.extruder_demand > 1 ? " — more than it gives" : ""));
    row("voids found by the slicer",
        fmt::format("{} ({:.0f} mm²)", m.planned_voids, m.planned_void_area_mm2));
    row("voids (deposit)", fmt::format("{} ({:.0f} cm³)", m.voids, m.void_volume_mm3 / 1000));
    row("ploughed by the roller", fmt::format("{:.1f} cm³", m.plough_volume_mm3 / 1000));
    row("bead laid over nothing", fmt::format("{:.0f} mm", m.unsupported_length_mm));
    row("corners too tight for the roller", fmt::format("{}", m.roller_corners));
    row("collisions", fmt::format("{}", m.collisions));
    if (m.min_layer_fill)
      row("layer fill (material / outline × height)",
          fmt::format("{:.3f} .. {:.3f}", *m.min_layer_fill, m.max_layer_fill.value_or(0)));
    row("min stock", m.cad && m.cad->min_stock_at_least ? "at most " + fmt_opt(m.min_stock_mm, "{:.2f} mm")
                                                        : fmt_opt(m.min_stock_mm, "{:.2f} mm"));
    row("undercut (share of the CAD surface the print falls short of)",
        m.undercut_fraction ? fmt::format("{:.1f} %", 100 * *m.undercut_fraction) : fmt_opt(std::nullopt));
    row("voxels", fmt::format("{} at {:.2f} mm", m.voxels, m.voxel_size_mm));
    row("thermal energy balance error", fmt::format("{:.1e}", m.thermal_energy_error));
    h += "</table>";
    h += fmt::format("<p>Print program: <a href=\"{0}\">{0}</a></p>", esc(v.program));
    h += files_html(v);
    h += "<h3>Sections</h3><table><tr><th class=l>section</th><th>layers</th><th>print time</th><th>mean "
         "layer time s</th><th>bead m</th><th>material kg</th><th>cost</th><th>interfaces</th><th>substrate "
         "°C "
         "at deposition min/mean/max</th><th>too hot %</th><th>too cold %</th><th>healing min/mean</th>"
         "<th class=l>verdict</th></tr>";
    for (const SectionRow& sr : v.metrics.sections) {
      const Stats3& s = sr.substrate_temp_c;
      h += fmt::format(
          "<tr><td class=l>{}</td><td>{}</td><td>{}</td><td>{:.0f}</td><td>{:.1f}</td><td>{:.2f}</td>"
          "<td>{:.2f}</td><td>{}</td><td>{}</td><td>{:.1f}</td><td>{:.1f}</td><td>{}</td><td "
          "class=l>{}</td></tr>",
          esc(sr.name), sr.layers, hms(sr.print_time_s), sr.mean_layer_time_s, sr.print_length_mm / 1000,
          sr.mass_kg, sr.material_cost, sr.interfaces, substrate_text(s), 100 * sr.too_hot_fraction,
          100 * sr.too_cold_fraction, healing_text(sr.healing, sr.healing_mean),
          thermal::to_string(sr.verdict));
    }
    h += "</table>";
    h += "<details open><summary>Layers</summary><table><tr><th>layer</th><th>z mm</th><th "
         "class=l>section</th><th>start s</th>"
         "<th>duration s</th><th>substrate °C at deposition min/mean/max</th><th>interfaces</th>"
         "<th>too hot %</th><th>too cold %</th><th>healing min/mean</th><th class=l>verdict</th>"
         "<th>layer time for the window s (typical)</th></tr>";
    for (const auto& l : v.layers) {
      const Stats3& s = l.substrate_temp_c;
      h += fmt::format(
          "<tr class=\"{}\"><td>{}</td><td>{:.1f}</td><td class=l>{}</td><td>{:.0f}</td><td>{:.1f}</td>"
          "<td>{}</td><td>{}</td><td>{:.1f}</td><td>{:.1f}</td><td>{}</td><td "
          "class=l>{}</td><td>{}</td></tr>",
          l.verdict == thermal::Verdict::kTooHot    ? "hot"
          : l.verdict == thermal::Verdict::kTooCold ? "cold"
                                                    : "",
          l.index, l.z_mm, esc(l.section), l.start_s, l.duration_s, substrate_text(s), l.interfaces,
          100 * l.too_hot_fraction, 100 * l.too_cold_fraction, healing_text(l.healing, l.healing_mean),
          thermal::to_string(l.verdict), window_text(l));
    }
    h += "</table></details>";
    h += defects_html(v.defects);
    h += "<details><summary>Time per stage</summary><table>";
    for (const auto& s : v.stage_times) row(s.name, fmt::format("{:.2f} s", s.seconds));
    row("all, wall clock",
        fmt::format("{:.2f} s (the CAD comparison runs beside the thermal stage)", v.wall_time_s));
    h += "</table></details>";
  }
  // Chart.js, then the script that draws the plots, at the end of the body: the plots' data is in place.
  h += "<script>" + std::string(chartjs_source()) + "</script>\n<script>" +
       std::string(report_plots_source()) + "</script>\n</body></html>\n";
  return h;
}

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

// A table cell for Markdown: the pipes a name may hold escaped.
std::string md(std::string_view text) {
  std::string out;
  for (const char c : text) {
    if (c == '|') out += '\\';
    out += c == '\n' ? ' ' : c;
  }
  return out;
}

std::string summary_md(const RunResult& result) {
  // Short enough for a pull-request comment: the verdict, the variants against the baseline (the first
  // kSummaryRows, the failed ones first), and the failed gates; the rest is in report.html.
  constexpr std::size_t kSummaryRows = 20;
  int failed_gates = 0;
  for (const auto& v : result.variants)
    for (const auto& g : v.gates) failed_gates += g.passed ? 0 : 1;
  std::string s = fmt::format(
      "## beadtwin: {} — {}\n\n", md(result.scenario ? result.scenario->name : ""),
      result.passed ? "passed"
                    : fmt::format("**failed** ({} gate{})", failed_gates, failed_gates == 1 ? "" : "s"));
  const std::size_t base = result.variants.empty() ? 0 : baseline_index(result.variants);
  const bool compare = result.variants.size() > 1;
  s += "| variant | verdict |";
  std::string rule = "|---|---|";
  for (const VariantColumn& c : variant_columns())
    if (c.in_summary) s += fmt::format(" {} |", c.heading), rule += "---|";
  s += "\n" + rule + "\n";
  std::vector<std::size_t> order(result.variants.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_partition(order.begin(), order.end(), [&](std::size_t i) { return i == base; });
  std::stable_partition(order.begin() + (order.empty() ? 0 : 1), order.end(),
                        [&](std::size_t i) { return !result.variants[i].passed; });
  for (std::size_t k = 0; k < order.size() && k < kSummaryRows; ++k) {
    const std::size_t i = order[k];
    const VariantResult& v = result.variants[i];
    s += fmt::format("| {}{} | {} |", md(v.name), compare && i == base ? " (baseline)" : "",
                     v.passed ? "pass" : "**fail**");
    for (const VariantColumn& c : variant_columns()) {
      if (!c.in_summary) continue;
      const VariantCell cell =
          variant_cell(c, v.metrics, i == base ? nullptr : &result.variants[base].metrics);
      s += " " + cell.text;
      if (!cell.delta.empty())
        s += cell.judgement < 0   ? fmt::format(" (**{}**, worse)", cell.delta)
             : cell.judgement > 0 ? fmt::format(" ({}, better)", cell.delta)
                                  : fmt::format(" ({})", cell.delta);
      s += " |";
    }
    s += "\n";
  }
  if (order.size() > kSummaryRows)
    s += fmt::format("\n{} more variants in report.html.\n", order.size() - kSummaryRows);
  int listed = 0;
  for (const std::size_t i : order)
    for (const auto& g : result.variants[i].gates) {
      if (g.passed) continue;
      if (listed++ == 0) s += "\n";
      if (listed > static_cast<int>(kSummaryRows)) continue;
      s += fmt::format("- {}: {}\n", md(result.variants[i].name), md(g.message));
    }
  if (listed > static_cast<int>(kSummaryRows))
    s += fmt::format("- and {} more failed gates in report.html\n", listed - static_cast<int>(kSummaryRows));
  return s;
}

void write_reports(const RunResult& result, const std::filesystem::path& dir) {
  write_file_atomic(dir / "report.json", report_json(result));
  write_file_atomic(dir / "report.html", report_html(result));
  write_file_atomic(dir / "junit.xml", junit_xml(result));
  write_file_atomic(dir / "summary.md", summary_md(result));
}

}  // namespace beadtwin::scenarios
