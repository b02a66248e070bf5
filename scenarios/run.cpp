#include "scenarios/run.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <mutex>
#include <optional>

#include <fmt/format.h>
#include <malloc.h>
#include <tbb/task_arena.h>

#include "core/atomic_file.hpp"
#include "core/memory.hpp"
#include "gcode/writer.hpp"
#include "render/surface.hpp"
#include "scenarios/input/metrics.hpp"
#include "scenarios/pictures.hpp"
#include "scenarios/report.hpp"
#include "scenarios/variant_run.hpp"
#include "sim/cad_compare.hpp"
#include "sim/deposit.hpp"
#include "sim/deposit_files.hpp"
#include "sim/skin.hpp"
#include "slicer/mesh.hpp"
#include "slicer/plan.hpp"
#include "thermal/snapshot_files.hpp"
#include "thermal/thermal.hpp"

namespace beadtwin::scenarios {
namespace {

Toolpath slice_variant(const Variant& v, slicer::PlanStats* stats = nullptr) {
  if (v.program) {
    // A program read as it was written: timed with this machine's motion.
    Toolpath tp = *v.program;
    if (tp.layers.empty())
      throw InputError({v.program_file.string(), 0, 0}, "program",
                       "the program deposits no material: there is nothing to simulate");
    time_toolpath(tp, v.machine.motion);
    return tp;
  }
  BT_CHECK(v.part.loaded != nullptr);
  Toolpath tp =
      slicer::plan_toolpath(*v.part.loaded, v.sections, v.machine.motion, stats, &v.machine.extruder);
  if (tp.layers.empty())
    throw InputError({}, "sections",
                     fmt::format("variant '{}': no section's Z range meets the part ({}), nothing to print",
                                 v.name, v.part.describe()));
  if (std::none_of(tp.moves.begin(), tp.moves.end(), [](const Move& m) { return m.deposits(); })) {
    // Layers, but no bead fits in any of them: the beads are wider than the part's sections.
    double widest = 0;
    for (const auto& s : v.sections) widest = std::max(widest, s.bead_width_mm);
    const Eigen::Vector3d size = v.part.loaded->max_corner() - v.part.loaded->min_corner();
    throw InputError(
        {}, "sections",
        fmt::format("variant '{}': no bead fits in any layer, nothing to print: the beads (up to "
                    "{:.4g} mm wide) are wider than the part's sections ({:.4g} x {:.4g} mm at "
                    "most); choose a narrower bead_width",
                    v.name, widest, size.x(), size.y()));
  }
  return tp;
}

// What the program writer needs of the sections (arc chord tolerance, melt settings) and of the extruder.
gcode::GcodeOptions gcode_options(const Variant& v) {
  gcode::GcodeOptions o;
  for (const auto& s : v.sections) {
    o.arc_tolerance_mm.push_back(s.arc_chord_tolerance_mm);
    o.melt.push_back(s.melt);
  }
  // Speed words need the pump's displacement; E words the filament's diameter.
  if (v.machine.extruder.has_commands()) o.extruder = &v.machine.extruder;
  return o;
}

// How the variant's thermal settings cut its beads into cells.
thermal::MeshOptions thermal_mesh_options(const Variant& v) {
  thermal::MeshOptions o;
  o.cells_across = v.thermal.cells_across;
  o.cells_through = v.thermal.cells_through;
  o.cell_length_mm = v.thermal.cell_length_mm;
  return o;
}

// What the thermal stage needs of the variant: its thermal settings, material and environment; the
// scenario's snapshots first (written as files), then the moments the pictures colour by temperature.
thermal::ThermalInput thermal_input(const Variant& v, const Toolpath& tp, const sim::Deposit& deposit,
                                    std::function<void(double)> progress, thermal::Communicator* ranks) {
  thermal::HeatOptions ho;
  ho.rel_tol = v.thermal.rel_tol;
  ho.abs_tol_k = v.thermal.abs_tol_k;
  ho.lump = v.thermal.lump;
  ho.birth_interval_s = v.thermal.birth_interval_s;
  ho.cooldown_s = v.thermal.cooldown_s;
  ho.sample_interval_s = v.thermal.sample_interval_s;
  for (const double t : v.thermal.snapshot_times_s)
    ho.snapshot_times_s.push_back(std::isinf(t) ? tp.total_time_s() : t);
  for (const double t : picture_snapshot_times(v.render, tp)) ho.snapshot_times_s.push_back(t);
  ho.progress = std::move(progress);
  ho.communicator = ranks;
  return {.toolpath = tp,
          .deposit = deposit,
          .material = v.material,
          .environment = v.machine.environment,
          .mesh = thermal_mesh_options(v),
          .heat = std::move(ho)};
}

// Bytes a thermal cell takes while the heat is solved: its links, the integrator's vectors, its history.
constexpr double kThermalBytesPerCell = 3000.0;
// Bytes a face of the surface takes once meshed, in everything the run builds from it.
constexpr double kSurfaceBytesPerFace = 280.0;
// The rest of what the later stages build: the pictures' frames, the CAD's scene.
constexpr double kLaterFixedBytes = 100e6;
// What the run holds once its deposit is made: the program's own, the moves with their motion plan and what
// the reader kept (per byte of moves), and the deposit's grids with what its work left to the allocator (per
// byte of grids).
constexpr double kHeldFixedBytes = 60e6;
constexpr double kHeldPerMoveByte = 2.1;
constexpr double kHeldPerGridByte = 1.6;

// Deposits a variant's toolpath, at `voxel_size_mm` when positive (else the variant's).
sim::Deposit deposit_variant(const Variant& v, const Toolpath& tp, std::function<void(double)> progress,
                             double voxel_size_mm = 0.0) {
  try {
    sim::DepositOptions o = deposit_options(v);
    if (voxel_size_mm > 0.0) o.voxel_size_mm = voxel_size_mm;
    o.progress = std::move(progress);
    return sim::deposit(tp, o);
  } catch (const InputError& e) {
    // The deposit knows the option, not where it was written: name the scenario's key.
    if (e.key() != "voxel_size") throw;
    throw InputError(v.output.voxel_size_at, "output.voxel_size", e.message());
  }
}

// Under mpirun, whether every rank goes on: rank 0 says, once it has checked what only it checks (false: it
// stopped on bad input). Every rank calls it once, before any thermal solve. Alone: `ok`.
bool ranks_agree(thermal::Communicator* ranks, bool ok) {
  if (ranks == nullptr) return ok;
  return ranks->gather_each(ok ? 1.0 : 0.0)[0] != 0.0;
}

// Bytes as a person reads them: "0.18 GB", "3.4 GB".
std::string gigabytes(double bytes) {
  return bytes < 10e9 ? fmt::format("{:.2f} GB", bytes / 1e9) : fmt::format("{:.1f} GB", bytes / 1e9);
}

// Under mpirun, the voxel size every rank deposits a variant at: rank 0's, said once its deposit is known to
// fit the memory budget (0: it stopped on that). Every rank calls it once after each variant's deposit.
// Alone: `mine`.
double agreed_voxel_size(thermal::Communicator* ranks, double mine) {
  return ranks == nullptr ? mine : ranks->gather_each(mine)[0];
}

// Deposits a variant and checks that the rest of the run fits the memory budget once the deposit's surface
// is known (RunMemory). Over it, a voxel size the scenario set is an error naming one that would
// fit; an automatic one is made coarser and the toolpath deposited again, with a note. `need` receives the
// estimate for the deposit returned. Under mpirun the other ranks deposit at the size settled on here
// (share_thermal).
sim::Deposit deposit_within_budget(const Variant& v, const Toolpath& tp,
                                   const std::function<void(double)>& progress, thermal::Communicator* ranks,
                                   RunMemory& need) {
  std::vector<std::string> notes;
  double size = 0.0;  // the variant's
  for (int attempt = 1;; ++attempt) {
    // The deposit found too large is gone: what it freed goes back to the system, not left to the allocator
    // (the PrusaSlicer program, deposited at 0.2 mm then at 0.4 mm: peak 3.70 GB without, 3.54 GB with).
    if (attempt > 1) (void)::malloc_trim(0);
    sim::Deposit d = deposit_variant(v, tp, progress, size);
    need = run_memory(v, tp, d);
    notes.insert(notes.end(), d.notes.begin(), d.notes.end());
    if (need.in_turn() <= need.budget) {
      (void)agreed_voxel_size(ranks, d.voxel_size_mm);
      d.notes = std::move(notes);
      return d;
    }
    const double fitting = need.fitting_voxel_mm(d.voxel_size_mm);  // above the voxel size, or 0
    const std::string faces = d.surface_faces >= 1'000'000
                                  ? fmt::format("{:.3g} million", static_cast<double>(d.surface_faces) / 1e6)
                                  : fmt::format("{}", d.surface_faces);
    const std::string over = fmt::format(
        "voxel size {} mm: once the deposit's surface is meshed ({} voxel faces) the run would need "
        "about {}, over the memory budget of {}",
        d.voxel_size_mm, faces, gigabytes(need.in_turn()), gigabytes(need.budget));
    if (v.output.voxel_size_mm > 0.0 || fitting == 0.0 || attempt == 3) {
      (void)agreed_voxel_size(ranks, 0.0);
      throw InputError(v.output.voxel_size_at, "output.voxel_size",
                       fitting > 0.0
                           ? fmt::format("{}; use a voxel size of {} mm or more, or raise "
                                         "output.memory_budget",
                                         over, fitting)
                           : fmt::format("{}; at any voxel size the rest of the run (the program, the "
                                         "thermal cells and what every run holds) needs about {}: "
                                         "raise output.memory_budget",
                                         over, gigabytes(need.least())));
    }
    notes.push_back(fmt::format("{}: {} mm used instead", over, fitting));
    size = fitting;
  }
}

// The variants a run runs: the ones named (all when none are).
std::vector<const Variant*> chosen_variants(const Scenario& sc, const RunOptions& options) {
  std::vector<const Variant*> chosen;
  for (const Variant& v : sc.variants)
    if (options.variants.empty() ||
        std::find(options.variants.begin(), options.variants.end(), v.name) != options.variants.end())
      chosen.push_back(&v);
  return chosen;
}

// Compares the deposit with the CAD the sections print; nullopt when there is none (a program, AM Outline
// sections). The band reaches the requested stock and a bead width beyond it (stocks beyond that are
// reported as "at least"), within 4..32 voxels.
// The CAD a variant's print is compared with, and how, on voxels of `voxel_mm`; nothing without one (a
// program simulated, or sections that print outlines).
struct CadPlan {
  slicer::TriangleMesh cad;
  sim::CadCompareOptions options;
  double requested_stock_mm = 0.0, map_half_range_mm = 0.0;
  sim::CadSurface surface() const { return {cad.vertices, cad.triangles}; }
};
std::optional<CadPlan> plan_cad_check(const Variant& v, double voxel_mm) {
  if (v.program || !v.part.loaded) return std::nullopt;
  std::optional<slicer::TriangleMesh> cad = slicer::printed_cad(*v.part.loaded, v.sections);
  if (!cad) return std::nullopt;
  const StockScale stock = stock_scale(v);
  CadPlan plan;
  plan.cad = std::move(*cad);
  plan.requested_stock_mm = stock.requested_mm;
  plan.map_half_range_mm = stock.half_range_mm;
  plan.options.requested_stock_mm = stock.requested_mm;
  plan.options.band_mm =
      std::clamp(std::abs(stock.requested_mm) + stock.widest_bead_mm, 4.0 * voxel_mm, 32.0 * voxel_mm);
  return plan;
}

// The part of the CAD check that needs no deposit, made while it runs: the plan and the CAD's distance grid
// on the voxels the deposit will use.
struct CadAhead {
  double voxel_mm = 0.0;
  CadPlan plan;
  sim::CadDistance distance;
};
std::optional<CadAhead> cad_check_ahead(const Variant& v, const Toolpath& tp) {
  if (v.program || !v.part.loaded) return std::nullopt;
  CadAhead ahead;
  try {
    ahead.voxel_mm = sim::deposit_voxel_size_mm(tp, deposit_options(v));
  } catch (const InputError&) {
    return std::nullopt;  // the deposit says what is wrong, naming the scenario's key
  }
  std::optional<CadPlan> plan = plan_cad_check(v, ahead.voxel_mm);
  if (!plan) return std::nullopt;
  ahead.plan = std::move(*plan);
  ahead.distance = sim::cad_distance(ahead.plan.surface(), ahead.voxel_mm, ahead.plan.options);
  return ahead;
}

// The print against its CAD, with what was made ahead for the deposit's voxels (else all of it here).
std::optional<CadCheck> check_against_cad(const Variant& v, const sim::Deposit& deposit,
                                          const std::optional<CadAhead>& ahead) {
  const bool usable = ahead && ahead->voxel_mm == deposit.voxel_size_mm;
  std::optional<CadPlan> fresh;
  if (!usable) fresh = plan_cad_check(v, deposit.voxel_size_mm);
  const CadPlan* plan = usable ? &ahead->plan : fresh ? &*fresh : nullptr;
  if (plan == nullptr) return std::nullopt;
  CadCheck check;
  check.requested_stock_mm = plan->requested_stock_mm;
  check.map_half_range_mm = plan->map_half_range_mm;
  check.comparison =
      sim::compare_with_cad(deposit, plan->surface(), plan->options, usable ? &ahead->distance : nullptr);
  return check;
}

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
  }
  return m;
}

// The report's numbers of a summary of interfaces.
FusionRow fusion_row(const thermal::FusionSummary& f) {
  FusionRow row;
  row.interfaces = static_cast<int>(f.interfaces);
  row.substrate_temp_c = {f.substrate_min_c, f.substrate_mean_c, f.substrate_max_c};
  row.healing = f.healing_min;
  row.healing_mean = f.healing_mean;
  row.too_hot = static_cast<int>(f.too_hot);
  row.too_cold = static_cast<int>(f.too_cold);
  row.too_hot_fraction = f.too_hot_fraction();
  row.too_cold_fraction = f.too_cold_fraction();
  row.verdict = f.verdict();
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

bool compare(double value, GateOp op, double threshold) {
  switch (op) {
    case GateOp::kLess:
      return value < threshold;
    case GateOp::kLessEqual:
      return value <= threshold;
    case GateOp::kGreater:
      return value > threshold;
    case GateOp::kGreaterEqual:
      return value >= threshold;
    case GateOp::kEqual:
      return value == threshold;
    case GateOp::kNotEqual:
      return value != threshold;
  }
  return false;
}

// The as-printed skin as a mesh file, with what the report says of it.
// From `surface` when given (the fill grid meshed at the skin's adaptivity), else meshed here.
void write_skin(const Variant& v, const Toolpath& tp, const sim::Deposit& deposit,
                const sim::FillSurface* surface, const std::filesystem::path& dir, ExportedFiles& files,
                std::vector<std::string>& notes) {
  const auto* format =
      std::find_if(std::begin(sim::kMeshFormats), std::end(sim::kMeshFormats),
                   [&](sim::MeshFormat f) { return sim::to_string(f) == v.output.skin_format; });
  BT_CHECK(format != std::end(sim::kMeshFormats));  // the loader accepts only these
  const std::string name = "skin." + v.output.skin_format;
  const sim::SkinMesh skin =
      surface ? sim::extract_skin(*surface, true, v.output.skin_tolerance_mm)
              : sim::extract_skin(deposit, v.output.skin_adaptivity, true, v.output.skin_tolerance_mm);
  if (skin.triangles.empty()) {
    // Simplified away: beads no thicker than the tolerance (a desktop bead against the 0.3 mm default).
    notes.push_back(
        fmt::format("no skin written: simplified to within output.skin_tolerance = {:.3g} mm, the "
                    "part's surface left no triangles (its beads are about that thin); a smaller "
                    "tolerance, or 0, keeps them",
                    v.output.skin_tolerance_mm));
    return;
  }
  sim::write_mesh(skin, dir / name, *format);
  files.skin = (std::filesystem::path(v.name) / name).string();
  files.skin_bytes = std::filesystem::file_size(dir / name);
  files.skin_triangles = skin.triangles.size();
  const sim::BeadStlEstimate beads = sim::bead_by_bead_stl(tp);
  files.bead_stl_triangles = beads.triangles;
  files.bead_stl_bytes = beads.bytes;
}

// The voxel fields for ParaView.
void write_fields(const Variant& v, const sim::Deposit& deposit, const std::filesystem::path& dir,
                  ExportedFiles& files) {
  files.fields_cells = sim::write_deposit_vtu(deposit, dir / "fields.vtu").cells;
  files.fields = (std::filesystem::path(v.name) / "fields.vtu").string();
  files.fields_bytes = std::filesystem::file_size(dir / "fields.vtu");
}

// A variant sliced before the run (so that its pictures can share a frame with the others').
struct Sliced {
  Toolpath toolpath;
  slicer::PlanStats stats;
  double seconds = 0.0;
};

VariantResult run_variant(const Scenario& sc, const Variant& v, const Sliced& sliced,
                          const PictureFrame& frame, const std::filesystem::path& out_dir,
                          const RunOptions& options) {
  const auto& log = options.log;
  VariantResult res;
  res.name = v.name;
  res.variant = &v;
  const auto started = std::chrono::steady_clock::now();
  const std::filesystem::path dir = out_dir / v.name;
  std::filesystem::create_directories(dir);
  // How far a stage has got, for the caller's progress bar.
  const auto progress_of = [&](const std::string& stage) -> std::function<void(double)> {
    if (!options.progress) return {};
    return [&options, &v, stage](double f) { options.progress(v.name, stage, f); };
  };
  Stages stages(log ? std::function<void(const std::string&)>(
                          [&](const std::string& line) { log(fmt::format("[{}] {}", v.name, line)); })
                    : std::function<void(const std::string&)>(),
                options.progress ? std::function<void(const std::string&)>([&](const std::string& stage) {
                  options.progress(v.name, stage, 0.0);
                })
                                 : std::function<void(const std::string&)>());

  stages.record("slice", sliced.seconds);
  const Toolpath& tp = sliced.toolpath;
  const slicer::PlanStats& plan_stats = sliced.stats;
  for (std::size_t i = 0; i < v.sections.size() && i < plan_stats.most_passes_laid.size(); ++i) {
    const int asked = v.sections[i].boundary.passes, laid = plan_stats.most_passes_laid[i];
    if (laid > 0 && laid < asked)
      res.notes.push_back(fmt::format(
          "section {}: boundary.passes is {}, but no layer had room for more than {} (each pass lays a bead "
          "along every contour of the layer, the outer and the inner side of a wall alike): more passes "
          "change nothing",
          v.sections[i].name, asked, laid));
  }
  stages.run("program", [&] {
    gcode::GcodeHeader header{v.name, sc.name, v.name, v.machine.name, v.material.name};
    write_file_atomic(dir / "program.nc",
                      gcode::write_gcode(tp, v.machine.dialect, header, gcode_options(v)));
  });
  res.program = (std::filesystem::path(v.name) / "program.nc").string();
  // The deposit keeps one core busy; the CAD's side of the comparison (its distance grid) needs only the
  // voxel size, so it is made on the other meanwhile. Its error, if any, is thrown by the comparison, after
  // the deposit's (the future waits as it is destroyed).
  std::future<std::optional<CadAhead>> cad_ahead = std::async(std::launch::async, [&] {
    tbb::task_arena one_core(1);  // the deposit has the other
    return one_core.execute([&] { return cad_check_ahead(v, tp); });
  });
  RunMemory need;
  const sim::Deposit deposit = stages.run("deposit", [&] {
    return deposit_within_budget(v, tp, progress_of("deposit"), options.thermal_ranks, need);
  });
  // Only the thermal stage and the pictures coloured by its results need it: the rest reads the deposit
  // alone and runs on a thread of its own beside the thermal stage: the CAD comparison, the deposit's files
  // (shared, below), the pictures' shapes (surfaces and ray-tracing scenes), the pictures that need no
  // thermal result, and the rays of those that do (traced now, coloured once it is done: PictureWriter). The
  // thermal stage keeps both cores busy only in its short parallel loops between the integrator's serial
  // steps, so the other thread mostly fills the gaps (docs/PERFORMANCE.md). The main thread touches none of
  // what that thread writes until it is done. The times of its stages are recorded once both are done, so the
  // stages keep one order; the render stage's time is both of its goes. An error of either is thrown after
  // both have finished (the future waits as it is destroyed).
  PictureInputs pictures_in;
  pictures_in.scenario = &sc;
  pictures_in.variant = &v;
  pictures_in.toolpath = &tp;
  pictures_in.deposit = &deposit;
  pictures_in.frame = &frame;
  // The fill grid's surface at adaptivity 0, meshed once for the skin and the pictures of the whole part
  // when the skin is meshed at that adaptivity (the default) and both are made beside the thermal stage
  // (below): by whichever comes to it first, dropped once both are done with it. Without room beside the
  // thermal stage each meshes its own, as the pictures' surfaces are then held through it.
  struct SharedSurface {
    std::mutex mutex;
    bool made = false;
    std::optional<sim::FillSurface> mesh;
    int users = 2;  // the skin and the pictures
    // The surface, or null once both are done with it.
    const sim::FillSurface* get(const sim::Deposit& d) {
      const std::lock_guard lock(mutex);
      if (!made) mesh = sim::mesh_fill(d, 0.0), made = true;
      return mesh ? &*mesh : nullptr;
    }
    void done() {
      const std::lock_guard lock(mutex);
      if (--users == 0) mesh.reset();
    }
  } shared_surface;
  bool share_surface = false;  // set below, before either uses it
  pictures_in.whole_surface = [&]() -> std::optional<render::SurfaceMesh> {
    if (!share_surface) return std::nullopt;
    const openvdb::Index64 active = deposit.fill->activeVoxelCount();
    const sim::FillSurface* s = active > 0 ? shared_surface.get(deposit) : nullptr;
    if (s == nullptr) return std::nullopt;  // the pictures say what is wrong themselves
    return render::surface_mesh(s->points_mm, s->triangles, s->quads, active);
  };
  struct Beside {
    std::optional<CadCheck> cad;
    std::optional<PictureWriter> pictures;
    std::vector<std::string> notes;  // the skin's
    double compare_s = 0.0, render_s = 0.0;
  } beside;
  const auto timed = [](double& seconds, const auto& work) {
    const auto t0 = std::chrono::steady_clock::now();
    work();
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  // The deposit's files, each written by whichever thread comes to it first: that thread once the comparison
  // is done (before the pictures, so that the skin's mesh is gone before the pictures' surfaces and scenes
  // are built: the LSAM mould peaked at 1.53 GB instead of 1.86 GB, in the same time), or this one once the
  // thermal stage is done (on a small part the thermal stage outlasts all of it). Each writes its own fields
  // of res.
  struct FileJob {
    std::atomic_flag taken;
    double seconds = 0.0;
    std::function<void()> work;  // none: not asked for
  };
  std::array<FileJob, 3> file_jobs;
  auto& [vdb_job, skin_job, fields_job] = file_jobs;
  vdb_job.work = [&] {
    sim::write_deposit_vdb(deposit, dir / "deposit.vdb");
    res.deposit_file = (std::filesystem::path(v.name) / "deposit.vdb").string();
    res.exported.deposit_bytes = std::filesystem::file_size(dir / "deposit.vdb");
  };
  if (!v.output.skin_format.empty())
    skin_job.work = [&] {
      if (!share_surface) return write_skin(v, tp, deposit, nullptr, dir, res.exported, beside.notes);
      const sim::FillSurface* surface = shared_surface.get(deposit);
      write_skin(v, tp, deposit, surface, dir, res.exported, beside.notes);
      shared_surface.done();
    };
  if (v.output.write_fields) fields_job.work = [&] { write_fields(v, deposit, dir, res.exported); };
  const auto write_files = [&] {
    for (FileJob& job : file_jobs)
      if (job.work && !job.taken.test_and_set()) timed(job.seconds, job.work);
  };
  const auto pictures_without_thermal = [&] {
    timed(beside.render_s, [&] {
      pictures_in.cad = beside.cad ? &*beside.cad : nullptr;
      beside.pictures.emplace(pictures_in, dir);
      beside.pictures->without_thermal();
    });
    if (share_surface) shared_surface.done();
  };
  // The pictures' surfaces and scenes and the skin, held or built while the thermal stage holds its own,
  // add to the run's peak: beside it only while the run would stay within the memory budget so
  // (RunMemory), else after it.
  const bool room_beside = need.side_by_side() <= need.budget / 1.1;  // a tenth to spare, as when coarsening
  share_surface = room_beside && !v.output.skin_format.empty() && v.output.skin_adaptivity == 0.0;
  std::future<void> beside_thermal = std::async(std::launch::async, [&] {
    timed(beside.compare_s, [&] { beside.cad = check_against_cad(v, deposit, cad_ahead.get()); });
    if (!room_beside) return;
    write_files();
    pictures_without_thermal();
  });
  const thermal::ThermalResult th = stages.run("thermal", [&] {
    return thermal::solve_thermal(
        thermal_input(v, tp, deposit, progress_of("thermal"), options.thermal_ranks));
  });
  if (room_beside) write_files();
  beside_thermal.get();
  if (!beside.pictures) pictures_without_thermal();
  const std::optional<CadCheck>& cad = beside.cad;
  stages.record("compare", beside.compare_s);
  for (const auto* notes : {&th.heat.notes, &th.mesh.notes})  // the thermal stage's choices
    res.notes.insert(res.notes.end(), notes->begin(), notes->end());
  if (th.heat.ranks > 1)
    res.notes.push_back(fmt::format("thermal: solved across {} MPI ranks, each a slice of the part by height",
                                    th.heat.ranks));
  if (!v.thermal.snapshot_times_s.empty())
    stages.run("snapshots", [&] {
      for (const thermal::TemperatureSnapshot& s : th.heat.snapshots) {
        if (s.request >= v.thermal.snapshot_times_s.size()) continue;  // taken for a picture only
        const std::string stem = fmt::format("temperature-{:.0f}s", s.time_s);
        thermal::write_temperature_vdb(th.mesh, s, dir / (stem + ".vdb"));
        thermal::write_temperature_vtp(th.mesh, s, dir / (stem + ".vtp"));
        const std::filesystem::path rel(v.name);
        res.exported.snapshots.push_back(
            {s.time_s, (rel / (stem + ".vdb")).string(), (rel / (stem + ".vtp")).string()});
      }
    });
  {
    if (options.progress) options.progress(v.name, "render", 0.0);
    const auto t0 = std::chrono::steady_clock::now();
    PictureFiles files = beside.pictures->finish(th);
    stages.record("render", beside.render_s +
                                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    const std::vector<std::string>& picture_notes = beside.pictures->notes();
    res.notes.insert(res.notes.end(), picture_notes.begin(), picture_notes.end());
    res.images = std::move(files.images);
    res.exr_images = std::move(files.exr);
    res.progress_frames = std::move(files.progress);
    beside.pictures.reset();  // the shapes
  }
  write_files();  // without room beside the thermal stage, all of them now, after the pictures
  stages.record("vdb", vdb_job.seconds);
  if (skin_job.work) stages.record("skin", skin_job.seconds);
  if (fields_job.work) stages.record("fields", fields_job.seconds);
  res.notes.insert(res.notes.end(), beside.notes.begin(), beside.notes.end());
  res.metrics = measure(v, tp, deposit, th);
  if (cad) put_cad_metrics(*cad, res.metrics);
  res.metrics.extruder_demand = worst_flow_excess(v.machine.extruder, tp).ratio;
  res.metrics.planned_voids = plan_stats.voids_found;
  res.metrics.planned_void_area_mm2 = plan_stats.void_area_mm2;
  res.layers = layer_rows(tp, th, deposit);
  res.metrics.sections = section_rows(tp, th, v.material);
  res.temperature_history = temperature_history(v, th.heat);
  res.defects = deposit.defects;
  res.notes.insert(res.notes.begin(), deposit.notes.begin(), deposit.notes.end());
  if (log)
    for (const std::string& n : res.notes) log(fmt::format("[{}] note: {}", v.name, n));
  res.stage_times = stages.times();
  res.wall_time_s =
      sliced.seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return res;
}

}  // namespace

sim::DepositOptions deposit_options(const Variant& v) {
  sim::DepositOptions o;
  o.voxel_size_mm = v.output.voxel_size_mm;
  o.flattening = v.machine.kind == MachineKind::kRollerGantry   ? sim::Flattening::kRoller
                 : v.machine.kind == MachineKind::kTamperGantry ? sim::Flattening::kTamper
                                                                : sim::Flattening::kNozzle;
  o.roller_width_mm = v.machine.roller_width_mm;
  o.roller_diameter_mm = v.machine.roller_diameter_mm;
  o.nozzle_diameter_mm = v.machine.nozzle_diameter_mm;
  o.ooze_time_s = v.machine.ooze_time_s;
  o.memory_budget_bytes = v.output.memory_budget_gb * 1e9;
  return o;
}

std::optional<sim::CadComparison> compare_variant_with_cad(const Variant& variant,
                                                           const sim::Deposit& deposit) {
  std::optional<CadCheck> check = check_against_cad(variant, deposit, std::nullopt);
  if (!check) return std::nullopt;
  return std::move(check->comparison);
}

double RunMemory::side_by_side() const {
  return program + deposit + kLaterFixedBytes + cells + grids + surfaces;
}

double RunMemory::in_turn() const {
  return program + deposit + kLaterFixedBytes + std::max(cells + grids, surfaces);
}

RunMemory RunMemory::at_voxel_ratio(double r) const {
  RunMemory m = *this;
  m.deposit *= r * r * r;
  m.grids *= r * r * r;
  m.surfaces *= r * r;
  return m;
}

double RunMemory::least() const {
  return program + kLaterFixedBytes + cells;
}

double RunMemory::fitting_voxel_mm(double voxel_mm) const {
  const double room = budget / 1.1;   // a tenth to spare
  if (!(least() < room)) return 0.0;  // no voxel size would do
  // Tenths of a millimetre above the voxel size, until the run fits: it does before the voxels are as
  // large as the room left over makes the deposit and its surface.
  for (double tenths = std::floor(voxel_mm * 10.0 + 1e-9) + 1.0;; tenths += 1.0)
    if (at_voxel_ratio(voxel_mm / (tenths / 10.0)).in_turn() <= room) return tenths / 10.0;
}

RunMemory run_memory(const Variant& v, const Toolpath& tp, const sim::Deposit& d) {
  RunMemory m;
  const auto bytes = [](const auto& grid) { return grid ? static_cast<double>(grid->memUsage()) : 0.0; };
  m.program = kHeldFixedBytes + kHeldPerMoveByte * static_cast<double>(tp.moves.size() * sizeof(Move));
  m.deposit =
      kHeldPerGridByte * (bytes(d.fill) + bytes(d.time) + bytes(d.layer) + bytes(d.move) + bytes(d.gaps));
  m.cells =
      kThermalBytesPerCell * static_cast<double>(thermal::planned_cell_count(tp, thermal_mesh_options(v)));
  m.grids = bytes(d.layer);  // the thermal stage's grid of cells is as large as the layer grid
  m.surfaces = kSurfaceBytesPerFace * static_cast<double>(d.surface_faces);
  m.budget = memory_budget_bytes(v.output.memory_budget_gb * 1e9);
  return m;
}

Toolpath variant_toolpath(const Variant& v) {
  return slice_variant(v);
}

namespace {

std::optional<double> lookup(const MetricValues& values, const std::string& name) {
  const auto it = values.find(name);
  return it == values.end() ? std::nullopt : std::optional<double>(it->second);
}

// The sections a run measured, from their sections.NAME.layers values (every section has its layer count).
std::vector<std::string> section_names(const MetricValues& values) {
  constexpr std::string_view kPrefix = "sections.", kSuffix = ".layers";
  std::vector<std::string> names;
  for (const auto& [name, value] : values)
    if (name.starts_with(kPrefix) && name.ends_with(kSuffix) && name.size() > kPrefix.size() + kSuffix.size())
      names.push_back(name.substr(kPrefix.size(), name.size() - kPrefix.size() - kSuffix.size()));
  return names;
}

}  // namespace

std::vector<GateResult> evaluate_gates(const std::vector<Gate>& gates, const MetricValues& values,
                                       const MetricValues* baseline) {
  std::vector<GateResult> out;
  for (const Gate& g : gates) {
    GateResult r;
    r.name = g.expr;
    r.expr = g.expr;
    r.value = lookup(values, g.metric);
    std::optional<double> threshold = g.threshold;
    const std::optional<double> base = baseline ? lookup(*baseline, g.metric) : std::nullopt;
    if (g.relative) {
      threshold = base ? std::optional<double>(*base * g.factor + g.offset) : std::nullopt;
      r.threshold = threshold;
    }
    if (!r.value) {
      r.passed = false;
      r.message = fmt::format("{} is not measured for this run", g.metric);
      if (const std::optional<std::string> section = gate_metric_section(g.metric)) {
        const std::vector<std::string> names = section_names(values);
        if (std::find(names.begin(), names.end(), *section) == names.end())
          r.message =
              fmt::format("{}: this run has no section '{}'; its sections are: {}", g.metric, *section,
                          names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", ")));
      }
    } else if (!threshold) {
      r.passed = false;
      r.message = baseline ? fmt::format("{} is not measured for the baseline", g.metric)
                           : std::string("there is no baseline variant to compare with");
    } else {
      r.passed = compare(*r.value, g.op, *threshold);
      if (!r.passed)
        r.message = g.relative ? fmt::format("{} = {:.6g}, required {} (baseline's: {:.6g}, so {:.6g})",
                                             g.metric, *r.value, g.expr, *base, *threshold)
                               : fmt::format("{} = {:.6g}, required {}", g.metric, *r.value, g.expr);
    }
    out.push_back(r);
  }
  return out;
}

std::vector<GateResult> evaluate_gates(const std::vector<Gate>& gates, const Metrics& metrics,
                                       const Metrics* baseline) {
  const MetricValues base = baseline ? baseline->values() : MetricValues{};
  return evaluate_gates(gates, metrics.values(), baseline ? &base : nullptr);
}

std::size_t baseline_index(const std::vector<VariantResult>& variants) {
  for (std::size_t i = 0; i < variants.size(); ++i)
    if (variants[i].name == "baseline") return i;
  return 0;
}

std::string slice_program(const Scenario& sc, const std::string& variant_name) {
  for (const Variant& v : sc.variants) {
    if (!variant_name.empty() && v.name != variant_name) continue;
    const Toolpath tp = slice_variant(v);
    return gcode::write_gcode(tp, v.machine.dialect,
                              {v.name, sc.name, v.name, v.machine.name, v.material.name}, gcode_options(v));
  }
  throw InputError({}, "--variant",
                   fmt::format("scenario '{}' has no variant named '{}'", sc.name, variant_name));
}

RunResult run_scenario(const Scenario& sc, const RunOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& name : options.variants) {
    if (std::none_of(sc.variants.begin(), sc.variants.end(),
                     [&](const Variant& v) { return v.name == name; })) {
      std::string names;
      for (const auto& v : sc.variants) names += (names.empty() ? "" : ", ") + v.name;
      throw InputError(
          {}, "--variant",
          fmt::format("scenario '{}' has no variant named '{}'; it has: {}", sc.name, name, names));
    }
  }
  try {
    check_gate_sections(sc);
    prepare_output_dir(options.out_dir, "--out");
  } catch (...) {
    (void)ranks_agree(options.thermal_ranks, false);
    throw;
  }
  (void)ranks_agree(options.thermal_ranks, true);
  // Everything is written into a staging folder and moved into place once the run is complete (the reports
  // last): a run that stops part-way leaves the previous run's files as they were.
  StagedDir staged(options.out_dir);
  const std::filesystem::path& stage = staged.dir();
  RunResult result;
  result.scenario = &sc;
  // Every variant sliced first: the pictures of all of them share one frame (camera box, colour scales).
  const std::vector<const Variant*> chosen = chosen_variants(sc, options);
  std::vector<Sliced> sliced;
  for (const Variant* v : chosen) {
    const auto t_slice = std::chrono::steady_clock::now();
    Sliced s;
    s.toolpath = slice_variant(*v, &s.stats);
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_slice).count();
    sliced.push_back(std::move(s));
  }
  std::vector<const Toolpath*> toolpaths;
  for (const Sliced& s : sliced) toolpaths.push_back(&s.toolpath);
  const PictureFrame frame = picture_frame(chosen, toolpaths, sc.inches);
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    result.variants.push_back(run_variant(sc, *chosen[i], sliced[i], frame, stage, options));
  }
  // The gates, once every variant has run: some compare with the baseline variant.
  if (!result.variants.empty()) {
    const Metrics baseline = result.variants[baseline_index(result.variants)].metrics;
    for (VariantResult& v : result.variants) {
      v.gates = evaluate_gates(sc.gates, v.metrics, &baseline);
      v.passed = std::all_of(v.gates.begin(), v.gates.end(), [](const GateResult& g) { return g.passed; });
      result.passed = result.passed && v.passed;
    }
  }
  result.sheets = write_sheets(result, stage);
  result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  write_reports(result, stage);
  staged.commit({"summary.md", "junit.xml", "report.html", "report.json"});
  return result;
}

bool share_thermal(const Scenario& sc, const RunOptions& options) {
  BT_CHECK(options.thermal_ranks != nullptr);
  if (!ranks_agree(options.thermal_ranks, true)) return false;
  // As rank 0: every variant sliced first, then each deposited and solved, in the same order.
  const std::vector<const Variant*> chosen = chosen_variants(sc, options);
  std::vector<Toolpath> toolpaths;
  for (const Variant* v : chosen) toolpaths.push_back(slice_variant(*v, nullptr));
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    sim::Deposit deposit = deposit_variant(*chosen[i], toolpaths[i], {});
    const double agreed = agreed_voxel_size(options.thermal_ranks, deposit.voxel_size_mm);
    if (agreed == 0.0) return false;        // rank 0 stopped: the run would not fit its memory budget
    if (agreed != deposit.voxel_size_mm) {  // rank 0 made it coarser to fit
      deposit = {};
      deposit = deposit_variant(*chosen[i], toolpaths[i], {}, agreed);
    }
    (void)thermal::solve_thermal(thermal_input(*chosen[i], toolpaths[i], deposit, {}, options.thermal_ranks));
  }
  return true;
}

}  // namespace beadtwin::scenarios
