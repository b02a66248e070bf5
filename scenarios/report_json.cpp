// report.json (scenarios/report.hpp): everything a run measured, for other programs.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <nlohmann/json.hpp>

#include "scenarios/input/metrics.hpp"
#include "scenarios/report.hpp"
#include "scenarios/report_parameters.hpp"
#include "scenarios/report_text.hpp"

namespace beadtwin::scenarios {
namespace {

// Defects listed by position (report.html lists fewer and points here for the rest).
constexpr std::size_t kDefectsInJson = 1000;

using nlohmann::json;

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

// A P10-P90 band: [p10, p90], null where not estimated.
json band_json(const Band& b) {
  if (std::isnan(b.p10) || std::isnan(b.p90)) return nullptr;
  return json::array({number_or_null(b.p10), number_or_null(b.p90)});
}

// The numbers of a layer's or a section's interfaces.
json fusion_json(const FusionRow& f) {
  return {{"substrate_temp_c", stats_json(f.substrate_temp_c)},
          {"surface_temp_c", stats_json(f.surface_temp_c)},
          {"support_limit_c", stats_json(f.support_limit_c)},
          {"slump_ratio_max", number_or_null(f.slump_ratio_max)},
          {"interfaces", f.interfaces},
          {"healing_min", number_or_null(f.healing)},
          {"healing_mean", number_or_null(f.healing_mean)},
          {"too_hot", f.too_hot},
          {"too_cold", f.too_cold},
          {"too_hot_fraction", f.too_hot_fraction},
          {"too_cold_fraction", f.too_cold_fraction},
          {"verdict", thermal::to_string(f.verdict)},
          {"marginal", f.marginal},
          {"bands",
           {{"substrate_temp_c", band_json(f.substrate_band_c)},
            {"surface_temp_c", band_json(f.surface_band_c)},
            {"healing", band_json(f.healing_band)},
            {"marginal_fraction", f.marginal_fraction},
            {"too_hot_fraction", {{"p10", f.too_hot_fraction_p10}, {"p90", f.too_hot_fraction_p90}}},
            {"too_cold_fraction", {{"p10", f.too_cold_fraction_p10}, {"p90", f.too_cold_fraction_p90}}}}}};
}

// A declared metric's value: null where it was not measured, a count as an integer.
template <class Row>
json metric_json(const MetricDecl<Row>& d, const Row& row) {
  const std::optional<double> v = d.read(row);
  if (!v) return nullptr;
  if (d.unit == MetricUnit::kCount) return static_cast<std::int64_t>(*v);
  return number_or_null(*v);
}

// Every part-wide metric, gate metric or diagnostic, at its dotted path (interfaces.count as "count" in
// "interfaces"), and the rest of the CAD comparison as "cad".
json metrics_json(const Metrics& m) {
  json out = {{"cad", cad_json(m)}};
  for (const MetricDef& d : metric_defs()) {
    std::string pointer = "/" + std::string(d.name);
    std::replace(pointer.begin(), pointer.end(), '.', '/');
    out[json::json_pointer(pointer)] = metric_json(d, m);
  }
  if (m.interfaces > 0) {  // the whole run's bands, as a layer's
    out["interfaces"]["bands"] = fusion_json(m.fusion)["bands"];
    out["interfaces"]["marginal"] = m.fusion.marginal;
  }
  return out;
}

json gates_json(const std::vector<GateResult>& gates) {
  json out = json::array();
  for (const auto& g : gates) {
    json gate = {{"name", g.name},
                 {"expr", g.expr},
                 {"value", optional_json(g.value)},
                 {"passed", g.passed},
                 {"message", g.message}};
    if (g.threshold) gate["threshold"] = *g.threshold;  // a relative gate's, from the baseline
    out.push_back(gate);
  }
  return out;
}

json layer_json(const LayerRow& l) {
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
  return row;
}

// A section's row: its interfaces as a layer's (fusion_json), and its own figures by their metric names.
json section_json(const SectionRow& s) {
  json row = fusion_json(s);
  row["name"] = s.name;
  for (const SectionMetricDef& d : section_metric_defs())
    if (!d.name.starts_with("interfaces.")) row[std::string(d.name)] = metric_json(d, s);
  return row;
}

json defects_json(const std::vector<sim::Defect>& defects) {
  json out = json::array();
  for (std::size_t i = 0; i < std::min(defects.size(), kDefectsInJson); ++i) {
    const sim::Defect& d = defects[i];
    out.push_back({{"kind", sim::to_string(d.kind)},
                   {"position_mm", {d.position_mm.x(), d.position_mm.y(), d.position_mm.z()}},
                   {"layer", d.layer},
                   {"move", d.move},
                   {"source_line", d.source_line > 0 ? json(d.source_line) : json(nullptr)},
                   {"size", d.size},
                   {"detail", d.detail}});
  }
  return out;
}

json variant_json(const VariantResult& r) {
  json layers = json::array(), sections = json::array(), stages = json::object();
  for (const LayerRow& l : r.layers) layers.push_back(layer_json(l));
  for (const SectionRow& s : r.metrics.sections) sections.push_back(section_json(s));
  for (const StageTime& s : r.stage_times) stages[s.name] = s.seconds;
  return {{"name", r.name},
          {"passed", r.passed},
          {"gates", gates_json(r.gates)},
          {"values", r.metrics.values()},  // every gate metric measured, by its name: what a sweep gathers
          {"metrics", metrics_json(r.metrics)},
          {"layers", layers},
          {"sections", sections},
          {"temperature_history", history_json(r.temperature_history)},
          {"defects", defects_json(r.defects)},
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

}  // namespace beadtwin::scenarios
