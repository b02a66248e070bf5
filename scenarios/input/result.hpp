// What a run produces for each variant: metrics, the per-layer table, gate results, and the
// files written. The report writers read only these types.
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/stages.hpp"
#include "scenarios/input/scenario.hpp"
#include "sim/defects.hpp"
#include "thermal/fusion.hpp"

namespace beadtwin::scenarios {

struct Stats3 {
  double min = 0, mean = 0, max = 0;
};

// A P10-P90 band; NaN where not estimated.
struct Band {
  double p10 = std::numeric_limits<double>::quiet_NaN(), p90 = std::numeric_limits<double>::quiet_NaN();
};

// The printed part against its CAD (sim/cad_compare.hpp, docs/physics.md), beyond the two headline numbers.
struct CadMetrics {
  double max_stock_mm = 0, mean_stock_mm = 0;                      // over the CAD surface, area-weighted
  double p05_stock_mm = 0, median_stock_mm = 0, p95_stock_mm = 0;  // area percentiles
  bool min_stock_at_least = false, max_stock_at_least = false;     // beyond the band: at least this far
  double requested_stock_mm = 0;                // the least outer stock the sections ask for
  double below_requested_stock_fraction = 0;    // share of the CAD surface with less stock than that
  double cad_area_mm2 = 0, plate_area_mm2 = 0;  // measured; left out as formed by the build plate
  // The printed skin's distance from the CAD (positive outside), area-weighted over the printed surface.
  double deviation_mean_mm = 0, deviation_rms_mm = 0, deviation_min_mm = 0, deviation_max_mm = 0;
  bool deviation_min_at_least = false, deviation_max_at_least = false;  // beyond the band
  double outside_volume_mm3 = 0;        // material outside the CAD: what machining removes
  double machining_waste_fraction = 0;  // ... as a share of the deposited volume
  double band_mm = 0;                   // distances are measured up to this far from each surface
  // The deviation map (deviation.png): white at requested_stock_mm, blue at requested − half range and
  // below, red at requested + half range and above.
  double map_half_range_mm = 0;
};

// What the interfaces where a layer's or a section's beads landed add up to (thermal/summary.hpp): the
// substrate's temperature where they landed on top and its surface's, as a thermal camera reads it just
// before the bead covers it (NaN: on nothing but the table), the least and the mean
// healing (NaN: no interface), how many interfaces were too hot or too cold and their share of the interface
// area, the verdict.
struct FusionRow {
  int interfaces = 0;
  Stats3 substrate_temp_c, surface_temp_c;
  // Where beads landed on top: the substrate temperature at which what was under them would just have
  // carried them (thermal::SupportResult::limit_c), and the most they slumped over what is allowed.
  Stats3 support_limit_c;
  double slump_ratio_max = 0;
  double healing = 0, healing_mean = 0;
  int too_hot = 0, too_cold = 0;
  double too_hot_fraction = 0, too_cold_fraction = 0;
  thermal::Verdict verdict = thermal::Verdict::kNoInterface;
  // Over the inputs' plausible ranges (thermal.uncertainty; thermal::FusionSummary): the P10-P90 bands of the
  // substrate's and the surface's mean temperature and of the mean healing (NaN without them), the share of
  // the area whose verdict changes within its bands, the shares too hot and too cold at the pessimistic
  // (p90) and optimistic (p10) end of each interface's bands, and whether the verdict, taken at either end,
  // changes (marginal).
  Band substrate_band_c, surface_band_c, healing_band;
  double marginal_fraction = 0;
  double too_hot_fraction_p10 = 0, too_hot_fraction_p90 = 0, too_cold_fraction_p10 = 0,
         too_cold_fraction_p90 = 0;
  bool marginal = false;
};

// A section's interfaces, as LayerRow has them per layer, and what it takes to print: its layers, the
// head's time in it (its moves, travels and dwells included), bead length, material (commanded volume at
// the material's density, which the deposit conserves) and cost, and its mean layer time.
struct SectionRow : FusionRow {
  std::string name;
  int layers = 0;
  double print_time_s = 0, print_length_mm = 0, commanded_volume_mm3 = 0, mass_kg = 0, material_cost = 0;
  double mean_layer_time_s = 0;
};

// Every gate metric a run measured, by its dotted name (a section's as sections.NAME.FIGURE): what gates
// read, what report.json keeps as "values", and what a sweep gathers from each variant.
using MetricValues = std::map<std::string, double>;

struct Metrics {
  int layers = 0;
  double print_time_s = 0, print_length_mm = 0, travel_length_mm = 0;
  double commanded_volume_mm3 = 0, deposited_volume_mm3 = 0, mass_kg = 0, material_cost = 0;
  double porosity = 0;
  // The part against its CAD: unset without a CAD to compare with (a program read as written, AM Outline
  // sections).
  std::optional<double> min_stock_mm;       // least stock left for machining over the CAD surface, mm;
                                            // negative: the print falls short of the CAD (undercut)
  std::optional<double> undercut_fraction;  // share of the CAD surface area with stock < 0
  std::optional<CadMetrics> cad;
  int interfaces = 0;
  double too_hot_fraction = 0, too_cold_fraction = 0, min_healing = 0, mean_healing = 0;
  // The whole part's bands and shares over the inputs' plausible ranges, as FusionRow has them per layer.
  FusionRow fusion;
  // Share of the interface area still at or above the healing threshold when the healing integral ended.
  double still_warm_fraction = 0;
  // The most the soft material under a landing bead slumped, over what the material allows; NaN: none landed
  // on another.
  double max_slump_ratio = std::numeric_limits<double>::quiet_NaN();
  Stats3 layer_time_s;
  // Void detection in the slicer (sections with voids.detect): uncovered pieces found and their area.
  int planned_voids = 0;
  double planned_void_area_mm2 = 0;
  // The most any move asks of the extruder, as a fraction of its limit (max flow or max RPM); above 1 the
  // program needs more than the extruder gives (reported, never clipped).
  double extruder_demand = 0;
  // Diagnostics beyond the gate metrics.
  double swept_volume_mm3 = 0, redistributed_volume_mm3 = 0;
  std::size_t voxels = 0;
  double voxel_size_mm = 0;
  double thermal_energy_error = 0;
  long thermal_steps = 0;
  double healing_followed_s = 0;  // after the last layer: the cooldown, or longer while interfaces were warm
  // Defects the deposit found (sim::Defect): voids of at least a voxel, material the roller ploughed,
  // bead laid over nothing, corners the roller cannot follow, the nozzle or roller running into the part.
  int voids = 0;
  double void_volume_mm3 = 0;
  double plough_volume_mm3 = 0;
  double unsupported_length_mm = 0;
  int roller_corners = 0;
  int collisions = 0;
  // Layers' commanded material over their outline times height (1: exactly full), the lowest and highest.
  std::optional<double> min_layer_fill, max_layer_fill;
  // Per section, in the toolpath's order.
  std::vector<SectionRow> sections;

  // The value of a declared metric (scenarios/input/metrics.hpp) by its dotted name, a section's figure as
  // sections.NAME.FIGURE; nullopt when not measured (or no section has that name). Throws InternalError on
  // a name not declared.
  std::optional<double> get(const std::string& name) const;
  // Every gate metric measured, by its name (those not measured are absent).
  MetricValues values() const;
};

struct LayerRow : FusionRow {
  int index = 0;
  double z_mm = 0;
  std::string section;
  double start_s = 0, duration_s = 0;
  // The layer times that would have put the layer in the window (thermal::layer_time_window), s; NaN
  // where nothing bounds them; min > max when none would.
  double window_min_s = 0, window_max_s = 0;
  double typical_min_s = 0, typical_max_s = 0;  // the same for half of the landing area
  // The deposit (sim::LayerDeposit): fill ratio (0: outline unknown), bead height after following the
  // substrate, void and ploughed volume, unsupported length.
  double fill_ratio = 0, bead_height_mm = 0, void_mm3 = 0, plough_mm3 = 0, unsupported_mm = 0;
};

// The mean temperature of chosen layers against time (output.history_layers), from the thermal model's
// samples (thermal::HeatResult::layer_temp_c: the volume-weighted mean over the layer's cells laid so far).
struct LayerHistory {
  int index = 0;              // toolpath layer, from 0
  std::vector<float> temp_c;  // per sample, °C; NaN before the layer's first cell is laid
};
struct TemperatureHistory {
  std::vector<double> times_s;  // every thermal.sample_interval from the first cell's birth
  std::vector<LayerHistory> layers;
};

struct GateResult {
  std::string name;  // the expression as written
  std::string expr;
  std::optional<double> value;
  std::optional<double> threshold;  // a relative gate's, from the baseline
  bool passed = false;
  std::string message;  // why it failed, when it did
};

// Files for other programs (sim/skin.hpp, sim/deposit_files.hpp): paths relative to the output directory,
// empty when not written.
struct ExportedFiles {
  std::uintmax_t deposit_bytes = 0;  // the .vdb
  std::string skin;                  // as-printed skin mesh, .ply or .stl
  std::uintmax_t skin_bytes = 0;
  std::size_t skin_triangles = 0;
  // A bead-by-bead STL of the same print (sim::bead_by_bead_stl): its triangles and its size.
  std::size_t bead_stl_triangles = 0;
  std::uintmax_t bead_stl_bytes = 0;
  // Temperature snapshots (thermal/snapshot_files.hpp): time, and the .vdb and .vtp files.
  struct Snapshot {
    double time_s = 0;
    std::string vdb, vtp;
  };
  std::vector<Snapshot> snapshots;
  std::string fields;  // voxel fields for ParaView, .vtu
  std::uintmax_t fields_bytes = 0;
  std::size_t fields_cells = 0;
};

struct VariantResult {
  std::string name;
  const Variant* variant = nullptr;
  Metrics metrics;
  std::vector<LayerRow> layers;
  TemperatureHistory temperature_history;
  std::vector<GateResult> gates;
  std::vector<std::string> images;           // PNG pictures, relative to the output directory
  std::vector<std::string> exr_images;       // the same as EXR with raw values (render.exr)
  std::vector<std::string> progress_frames;  // one per layer (or per render.progress.every layers)
  std::string program;                       // relative path of the print program
  std::string deposit_file;                  // relative path of the .vdb
  ExportedFiles exported;
  std::vector<StageTime> stage_times;  // may overlap: the CAD comparison runs beside the thermal stage
  double wall_time_s = 0;              // of the variant's stages, slicing included
  std::vector<sim::Defect> defects;  // what the deposit found, in toolpath order (voids last, largest first)
  std::vector<std::string> notes;    // what the stages chose for the user (a coarser voxel size, ...)
  bool passed = true;
};

struct RunResult {
  const Scenario* scenario = nullptr;
  std::vector<VariantResult> variants;
  std::vector<std::string> sheets;  // comparison sheets of the variants' pictures, relative paths
  bool passed = true;
  double wall_time_s = 0;
};

}  // namespace beadtwin::scenarios
