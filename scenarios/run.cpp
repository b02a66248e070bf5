#include "scenarios/run.hpp"

#include <algorithm>
#include <chrono>
#include <deque>
#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/atomic_file.hpp"
#include "core/percentile.hpp"
#include "scenarios/beside.hpp"
#include "scenarios/exports.hpp"
#include "scenarios/gate_results.hpp"
#include "scenarios/measure.hpp"
#include "scenarios/pictures.hpp"
#include "scenarios/report.hpp"
#include "scenarios/run_memory.hpp"
#include "scenarios/variant_outputs.hpp"
#include "scenarios/variant_run.hpp"
#include "scenarios/variant_stages.hpp"
#include "sim/deposit.hpp"
#include "slicer/plan.hpp"
#include "thermal/thermal.hpp"

namespace beadtwin::scenarios {
namespace {

// Under mpirun, whether every rank goes on: rank 0 says, once it has checked what only it checks (false: it
// stopped on bad input). Every rank calls it once, before any thermal solve. Alone: `ok`.
bool ranks_agree(thermal::Communicator* ranks, bool ok) {
  if (ranks == nullptr) return ok;
  return ranks->gather_each(ok ? 1.0 : 0.0)[0] != 0.0;
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

// A variant sliced before the run (so that its pictures can share a frame with the others').
struct Sliced {
  Toolpath toolpath;
  slicer::PlanStats stats;
};

// The notes of the planner's choices: sections whose boundary passes found no room.
void note_passes_laid(const Variant& v, const slicer::PlanStats& plan, std::vector<std::string>& notes) {
  for (std::size_t i = 0; i < v.sections.size() && i < plan.most_passes_laid.size(); ++i) {
    const int asked = v.sections[i].boundary.passes, laid = plan.most_passes_laid[i];
    if (laid > 0 && laid < asked)
      notes.push_back(fmt::format(
          "section {}: boundary.passes is {}, but no layer had room for more than {} (each pass lays a bead "
          "along every contour of the layer, the outer and the inner side of a wall alike): more passes "
          "change nothing",
          v.sections[i].name, asked, laid));
  }
}

// The notes of the thermal stage's choices.
// Where a bead's conduction time through its height, h²/α, is not short against the time before the next
// layer covers it (the median layer time under 2.5 times it), one cell through the bead does not resolve
// its cooling from the top, and healing comes out optimistic (docs/validation.md, mesh convergence). Measured
// between one and two cells through, in mean healing and too-cold fraction: the default box, its layer time
// 1.3 times h²/α, 0.03 and 0.13; a PrusaSlicer box (tests/data/prusa_box.gcode), 3.3 times, 0.007 and 0.01;
// a desktop PLA wall, 17 times, 0.001 (and the Compton wall, 0.8 times, up to 0.06 in a layer's mean). 2.5
// lies between the box and the PrusaSlicer box: a judgement, not a measured bound.
std::optional<std::string> resolution_note(const Variant& v, const Toolpath& tp) {
  if (v.thermal.cells_through > 1) return std::nullopt;
  std::vector<double> heights, layer_times;
  for (std::size_t l = 0; l < tp.layers.size(); ++l) {
    if (!(tp.layers[l].duration_s() > 0.0)) continue;
    heights.push_back(tp.layers[l].height_mm);
    if (l + 1 < tp.layers.size() && tp.layers[l + 1].duration_s() > 0.0)
      layer_times.push_back(tp.layers[l + 1].start_s - tp.layers[l].start_s);
  }
  if (layer_times.empty()) return std::nullopt;
  const Material& m = v.material;
  const double alpha_m2_s =
      m.conductivity_through_W_mK / (m.density_kg_m3 * m.specific_heat_at(m.deposition_temp_c));
  const double h_m = median(heights) * 1e-3;
  const double conduction_s = h_m * h_m / alpha_m2_s, layer_s = median(layer_times);
  if (!(layer_s < 2.5 * conduction_s)) return std::nullopt;
  return fmt::format(
      "thermal: one cell through beads {:.3g} mm high, whose conduction time h²/α ({:.3g} s) is not short "
      "against the layer time ({:.3g} s, median): a young bead's cooling from its top is not resolved, and "
      "healing comes out optimistic (on the shipped large-format scenarios by up to 0.06 in a layer's mean, "
      "the too-cold fraction by up to 0.13: docs/validation.md, mesh convergence); "
      "thermal.cells_through: 2 checks a verdict that decides, at about twice the thermal stage's cost",
      h_m * 1e3, conduction_s, layer_s);
}

void note_thermal(const Variant& v, const Toolpath& tp, const thermal::ThermalResult& th,
                  std::vector<std::string>& notes) {
  for (const auto* n : {&th.heat.notes, &th.mesh.notes}) notes.insert(notes.end(), n->begin(), n->end());
  if (!th.mesh.cells.empty())
    if (std::optional<std::string> note = resolution_note(v, tp)) notes.push_back(std::move(*note));
  if (th.heat.ranks > 1)
    notes.push_back(fmt::format("thermal: solved across {} MPI ranks, each a slice of the part by height",
                                th.heat.ranks));
  if (!th.uncertain_inputs.empty())
    notes.push_back(fmt::format(
        "thermal: P10-P90 bands over the plausible ranges of {} ({} more heat solves, {} more healing "
        "integrals; thermal.uncertainty: off leaves them out)",
        fmt::join(th.uncertain_inputs, ", "), th.extra_heat_solves, th.extra_healing_laws));
  else if (!th.mesh.cells.empty()) {
    // Without the bands the verdicts stand on the files' values alone: say how many of them are uncertain.
    std::vector<std::string> ranged;
    for (const auto* ranges : {&v.material.ranges, &v.machine.environment.ranges})
      for (const InputRange& r : *ranges) ranged.push_back(r.key);
    if (!ranged.empty())
      notes.push_back(fmt::format(
          "thermal: the verdicts are at the material and machine files' values, and {} of the inputs that "
          "decide them have plausible ranges there ({}), many of them estimates; thermal.uncertainty: "
          "linearised gives each layer's P10-P90 band and calls a verdict whose band crosses its threshold "
          "marginal",
          ranged.size(), fmt::join(ranged, ", ")));
  }
}

// What a variant's run shares with the others: the scenario, the pictures' frame, where it writes, how.
struct RunContext {
  const Scenario* scenario = nullptr;
  const PictureFrame* frame = nullptr;
  std::filesystem::path out_dir;
  const RunOptions* options = nullptr;

  // How far `variant`'s `stage` has got, for the caller's progress bar (empty: not asked for).
  std::function<void(double)> progress(const Variant& variant, const std::string& stage) const {
    if (!options->progress) return {};
    return [this, &variant, stage](double f) { options->progress(variant.name, stage, f); };
  }
  // The variant's stages, logged and announced as the options ask.
  std::function<void(const std::string&)> log(const Variant& variant) const {
    if (!options->log) return {};
    return [this, &variant](const std::string& line) {
      options->log(fmt::format("[{}] {}", variant.name, line));
    };
  }
  std::function<void(const std::string&)> on_start(const Variant& variant) const {
    if (!options->progress) return {};
    return [this, &variant](const std::string& stage) { options->progress(variant.name, stage, 0.0); };
  }
};

// One variant through the pipeline: program, deposit, thermal stage, CAD comparison, files, pictures and
// metrics, each a stage timed in `stages` (which holds its slicing already).
VariantResult run_variant(const RunContext& run, const Variant& v, const Sliced& sliced, Stages& stages) {
  const auto started = std::chrono::steady_clock::now();
  VariantResult res{.name = v.name, .variant = &v};
  const Toolpath& tp = sliced.toolpath;
  note_passes_laid(v, sliced.stats, res.notes);
  const std::filesystem::path dir = run.out_dir / v.name;
  std::filesystem::create_directories(dir);
  res.program = stages.run("program", [&] { return write_program(*run.scenario, v, tp, dir); });
  // The deposit keeps one core busy; the CAD's distance grid needs only the voxel size: made on the other.
  auto cad_ahead = on_one_core([&] { return cad_check_ahead(v, tp); });
  RunMemory need;
  const sim::Deposit deposit = stages.run("deposit", [&] {
    return deposit_within_budget(v, tp, run.progress(v, "deposit"), run.options->thermal_ranks, need);
  });
  // The rest but the pictures coloured by the thermal stage reads the deposit alone: beside the thermal
  // stage while the run stays within its memory budget so, with a tenth to spare, else after it.
  const bool room = need.side_by_side() <= need.budget / 1.1;
  VariantOutputs outputs(
      {.scenario = run.scenario, .variant = &v, .toolpath = &tp, .deposit = &deposit, .frame = run.frame},
      dir, res, stages, room);
  std::optional<CadCheck> cad;
  const thermal::ThermalResult th = beside(
      [&] {
        thermal::ThermalResult r = stages.run("thermal", [&] {
          return thermal::solve_thermal(
              thermal_input(v, tp, deposit, run.progress(v, "thermal"), run.options->thermal_ranks));
        });
        if (room) outputs.write_files();
        return r;
      },
      [&] {
        stages.run_aside("compare", [&] { cad = check_against_cad(v, deposit, cad_ahead.get()); });
        if (room) outputs.write_files(), outputs.pictures_without_thermal(cad ? &*cad : nullptr);
      });
  stages.record_aside("compare");
  note_thermal(v, tp, th, res.notes);
  if (!v.thermal.snapshot_times_s.empty())
    stages.run("snapshots", [&] { write_snapshots(v, th, dir, res.exported); });
  outputs.finish(th, cad ? &*cad : nullptr);
  measure_variant(v, tp, sliced.stats, deposit, th, cad, res);
  res.notes.insert(res.notes.begin(), deposit.notes.begin(), deposit.notes.end());
  if (run.options->log)
    for (const std::string& n : res.notes) run.options->log(fmt::format("[{}] note: {}", v.name, n));
  res.stage_times = stages.times();
  res.wall_time_s = stages.times().front().seconds +  // the slicing, before the others'
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return res;
}

}  // namespace

std::string slice_program(const Scenario& sc, const std::string& variant_name) {
  for (const Variant& v : sc.variants) {
    if (!variant_name.empty() && v.name != variant_name) continue;
    return program_text(sc, v, variant_toolpath(v));
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
  RunContext run{.scenario = &sc, .frame = nullptr, .out_dir = stage, .options = &options};
  std::deque<Stages> stages;  // each variant's, from its slicing on
  std::vector<Sliced> sliced;
  for (const Variant* v : chosen) {
    Stages& st = stages.emplace_back(run.log(*v), run.on_start(*v));
    Sliced& s = sliced.emplace_back();
    s.toolpath = st.run("slice", [&] { return variant_toolpath(*v, &s.stats); });
  }
  std::vector<const Toolpath*> toolpaths;
  for (const Sliced& s : sliced) toolpaths.push_back(&s.toolpath);
  const PictureFrame frame = picture_frame(chosen, toolpaths, sc.inches);
  run.frame = &frame;
  for (std::size_t i = 0; i < chosen.size(); ++i)
    result.variants.push_back(run_variant(run, *chosen[i], sliced[i], stages[i]));
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
  for (const Variant* v : chosen) toolpaths.push_back(variant_toolpath(*v, nullptr));
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
