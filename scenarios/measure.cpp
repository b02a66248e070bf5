#include "scenarios/measure.hpp"

#include <algorithm>
#include <vector>

#include "core/flow.hpp"

namespace beadtwin::scenarios {
namespace {

void put_cad_metrics(const CadCheck& check, Metrics& m) {
  const sim::CadComparison& c = check.comparison;
  m.min_stock_mm = c.min_stock_mm;
  m.undercut_fraction = c.undercut_fraction;
  CadMetrics& d = m.cad.emplace();
  d.max_stock_mm = c.max_stock_mm;
  d.mean_stock_mm = c.mean_stock_mm;
  d.p05_stock_mm = c.p05_stock_mm;
  d.median_stock_mm = c.median_stock_mm;
  d.p95_stock_mm = c.p95_stock_mm;
  d.min_stock_at_least = c.min_stock_clamped;
  d.max_stock_at_least = c.max_stock_clamped;
  d.requested_stock_mm = check.requested_stock_mm;
  d.below_requested_stock_fraction = c.below_requested_stock_fraction;
  d.cad_area_mm2 = c.cad_area_mm2;
  d.plate_area_mm2 = c.plate_area_mm2;
  d.deviation_mean_mm = c.deviation_mean_mm;
  d.deviation_rms_mm = c.deviation_rms_mm;
  d.deviation_min_mm = c.deviation_min_mm;
  d.deviation_max_mm = c.deviation_max_mm;
  d.deviation_min_at_least = c.deviation_min_clamped;
  d.deviation_max_at_least = c.deviation_max_clamped;
  d.outside_volume_mm3 = c.outside_volume_mm3;
  d.machining_waste_fraction = c.machining_waste_fraction;
  d.band_mm = c.band_mm;
  d.map_half_range_mm = check.map_half_range_mm;
}

Stats3 stats_of(const std::vector<double>& values) {
  Stats3 s;
  if (values.empty()) return s;
  s.min = *std::min_element(values.begin(), values.end());
  s.max = *std::max_element(values.begin(), values.end());
  double sum = 0;
  for (double v : values) sum += v;
  s.mean = sum / static_cast<double>(values.size());
  return s;
}

FusionRow fusion_row(const thermal::FusionSummary& f);

Metrics measure(const Variant& v, const Toolpath& tp, const sim::Deposit& d,
                const thermal::ThermalResult& th) {
  Metrics m;
  m.layers = static_cast<int>(tp.layers.size());
  m.print_time_s = tp.total_time_s();
  m.print_length_mm = tp.print_length_mm();
  m.travel_length_mm = tp.travel_length_mm();
  m.commanded_volume_mm3 = tp.commanded_volume_mm3();
  m.deposited_volume_mm3 = d.deposited_volume_mm3;
  m.mass_kg = d.deposited_volume_mm3 * 1e-9 * v.material.density_kg_m3;
  m.material_cost = m.mass_kg * v.material.price_per_kg;
  m.porosity = d.porosity;
  m.swept_volume_mm3 = d.swept_volume_mm3;
  m.redistributed_volume_mm3 = d.redistributed_volume_mm3;
  m.voxels = d.active_voxels;
  m.voxel_size_mm = d.voxel_size_mm;
  m.void_volume_mm3 = d.void_volume_mm3;
  m.voids = static_cast<int>(d.void_count);
  m.plough_volume_mm3 = d.plough_volume_mm3;
  m.unsupported_length_mm = d.unsupported_length_mm;
  for (const sim::Defect& x : d.defects) {
    m.roller_corners += x.kind == sim::DefectKind::kRollerCorner;
    m.collisions += x.kind == sim::DefectKind::kCollision;
  }
  for (const sim::LayerDeposit& l : d.layers) {
    if (!(l.fill_ratio > 0)) continue;
    m.min_layer_fill = std::min(m.min_layer_fill.value_or(l.fill_ratio), l.fill_ratio);
    m.max_layer_fill = std::max(m.max_layer_fill.value_or(l.fill_ratio), l.fill_ratio);
  }
  m.thermal_energy_error = th.heat.energy_balance_rel_error;
  m.thermal_steps = th.heat.steps;
  if (!th.heat.interfaces.empty())
    m.healing_followed_s = th.heat.healing_end_s - (th.heat.end_time_s - v.thermal.cooldown_s);
  std::vector<double> durations;
  for (const ToolpathLayer& l : tp.layers) durations.push_back(l.duration_s());
  m.layer_time_s = stats_of(durations);
  const thermal::FusionSummary part = thermal::summarise_part(th.heat);
  m.interfaces = static_cast<int>(part.interfaces);
  if (part.interfaces > 0) {
    m.too_hot_fraction = part.too_hot_fraction();
    m.too_cold_fraction = part.too_cold_fraction();
    m.min_healing = part.healing_min;
    m.mean_healing = part.healing_mean;
    m.still_warm_fraction = part.still_warm_fraction();
    m.max_slump_ratio = part.slump_ratio_max;
    m.fusion = fusion_row(part);
  }
  return m;
}

// The report's numbers of a summary of interfaces.
FusionRow fusion_row(const thermal::FusionSummary& f) {
  FusionRow row;
  row.interfaces = static_cast<int>(f.interfaces);
  row.substrate_temp_c = {f.substrate.min_c, f.substrate.mean_c, f.substrate.max_c};
  row.surface_temp_c = {f.surface.min_c, f.surface.mean_c, f.surface.max_c};
  row.support_limit_c = {f.support_limit.min_c, f.support_limit.mean_c, f.support_limit.max_c};
  row.slump_ratio_max = f.slump_ratio_max;
  row.healing = f.healing_min;
  row.healing_mean = f.healing_mean;
  row.too_hot = static_cast<int>(f.too_hot);
  row.too_cold = static_cast<int>(f.too_cold);
  row.too_hot_fraction = f.too_hot_fraction();
  row.too_cold_fraction = f.too_cold_fraction();
  row.verdict = f.verdict();
  row.substrate_band_c = {f.substrate_p10_c, f.substrate_p90_c};
  row.surface_band_c = {f.surface_p10_c, f.surface_p90_c};
  row.healing_band = {f.healing_p10, f.healing_p90};
  row.marginal_fraction = f.share(f.marginal_area_mm2);
  row.too_hot_fraction_p10 = f.share(f.too_hot_p10_area_mm2);
  row.too_hot_fraction_p90 = f.share(f.too_hot_p90_area_mm2);
  row.too_cold_fraction_p10 = f.share(f.too_cold_p10_area_mm2);
  row.too_cold_fraction_p90 = f.share(f.too_cold_p90_area_mm2);
  row.marginal = f.marginal_verdict();
  return row;
}

std::vector<LayerRow> layer_rows(const Toolpath& tp, const thermal::ThermalResult& th,
                                 const sim::Deposit& d) {
  std::vector<LayerRow> rows;
  for (std::size_t i = 0; i < tp.layers.size(); ++i) {
    const ToolpathLayer& l = tp.layers[i];
    const thermal::FusionSummary& f = th.layers[i];
    LayerRow row;
    static_cast<FusionRow&>(row) = fusion_row(f);
    row.index = static_cast<int>(i);
    row.z_mm = l.z_mm;
    row.section = l.section >= 0 ? tp.sections[static_cast<std::size_t>(l.section)] : "";
    row.start_s = l.start_s;
    row.duration_s = l.duration_s();
    row.window_min_s = f.layer_time_min_s;
    row.window_max_s = f.layer_time_max_s;
    row.typical_min_s = f.typical_time_min_s;
    row.typical_max_s = f.typical_time_max_s;
    if (i < d.layers.size()) {
      const sim::LayerDeposit& ld = d.layers[i];
      row.fill_ratio = ld.fill_ratio;
      row.bead_height_mm = ld.mean_bead_height_mm;
      row.void_mm3 = ld.void_volume_mm3;
      row.plough_mm3 = ld.plough_volume_mm3;
      row.unsupported_mm = ld.unsupported_length_mm;
    }
    rows.push_back(row);
  }
  return rows;
}

std::vector<SectionRow> section_rows(const Toolpath& tp, const thermal::ThermalResult& th,
                                     const Material& material) {
  std::vector<int> section_of_cell;
  section_of_cell.reserve(th.mesh.cells.size());
  for (const thermal::ThermalCell& c : th.mesh.cells) section_of_cell.push_back(tp.moves[c.move].section);
  const std::vector<thermal::FusionSummary> sums =
      thermal::summarise_groups(th.heat, section_of_cell, tp.sections.size());
  std::vector<SectionRow> rows;
  for (std::size_t k = 0; k < sums.size(); ++k) {
    SectionRow row;
    static_cast<FusionRow&>(row) = fusion_row(sums[k]);
    row.name = tp.sections[k];
    rows.push_back(row);
  }
  for (const Move& m : tp.moves) {
    if (m.section < 0 || static_cast<std::size_t>(m.section) >= rows.size()) continue;
    SectionRow& row = rows[static_cast<std::size_t>(m.section)];
    row.print_time_s += m.duration_s;
    if (m.deposits()) row.print_length_mm += m.length_mm();
    row.commanded_volume_mm3 += m.volume_mm3;
  }
  for (const ToolpathLayer& l : tp.layers) {
    if (l.section < 0 || static_cast<std::size_t>(l.section) >= rows.size()) continue;
    SectionRow& row = rows[static_cast<std::size_t>(l.section)];
    ++row.layers;
    row.mean_layer_time_s += l.duration_s();
  }
  for (SectionRow& row : rows) {
    row.mass_kg = row.commanded_volume_mm3 * 1e-9 * material.density_kg_m3;
    row.material_cost = row.mass_kg * material.price_per_kg;
    if (row.layers > 0) row.mean_layer_time_s /= row.layers;
  }
  return rows;
}

// The layers' temperature against time that the report keeps: the chosen layers the print reaches.
TemperatureHistory temperature_history(const Variant& v, const thermal::HeatResult& heat) {
  TemperatureHistory out;
  out.times_s = heat.sample_times_s;
  for (const int index : v.output.history_layers) {
    const auto i = static_cast<std::size_t>(index);
    if (index < 0 || i >= heat.layer_temp_c.size()) continue;
    out.layers.push_back({index, heat.layer_temp_c[i]});
  }
  return out;
}

}  // namespace

void measure_variant(const Variant& v, const Toolpath& tp, const slicer::PlanStats& plan,
                     const sim::Deposit& deposit, const thermal::ThermalResult& th,
                     const std::optional<CadCheck>& cad, VariantResult& res) {
  res.metrics = measure(v, tp, deposit, th);
  if (cad) put_cad_metrics(*cad, res.metrics);
  res.metrics.extruder_demand = worst_flow_excess(v.machine.extruder, tp).ratio;
  res.metrics.planned_voids = plan.voids_found;
  res.metrics.planned_void_area_mm2 = plan.void_area_mm2;
  res.layers = layer_rows(tp, th, deposit);
  res.metrics.sections = section_rows(tp, th, v.material);
  res.temperature_history = temperature_history(v, th.heat);
  res.defects = deposit.defects;
}

}  // namespace beadtwin::scenarios
