// The thermal benchmark: a scenario's first variant sliced and deposited as a run does, then its
// thermal mesh built and the heat transfer solved, each timed inside the process. Prints the mesh, the
// integrator's work, the energy balance, the verdicts and the real-time factor (simulated print time over
// the solve's wall time). bench/bench_thermal.sh runs it with /usr/bin/time for the peak memory.
//
// Built as thermal_ranks_bench (with MPI), it shares the solve among the ranks it is started with
// (`mpirun -n N thermal_ranks_bench ...`; rank 0 prints): bench/thermal_ranks.sh. THERMAL_BENCH_THREADS=N
// limits each process to N threads.
//
//   thermal_bench SCENARIO [BIRTH_INTERVAL_S [REL_TOL ABS_TOL_K]]   (0: the default)
//
// THERMAL_BENCH_VOXEL=MM deposits at that voxel size instead of the scenario's. THERMAL_BENCH_KINDS=1 also
// prints the interfaces by kind (on top of the layer below, on top of another, beside one in the same
// layer, beside another), each with its share of the interface area, its share too cold, its healing and
// its substrate temperature (area-weighted), the healing of those on the layer below by substrate
// temperature (5 K bins, from layer 12 on) and by whether either cell has surface open for good, and the
// contact between cells of neighbouring and of the same layers over layers 20-40 (docs/validation.md, mesh
// convergence).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include <openvdb/openvdb.h>
#include <tbb/global_control.h>
#ifdef BEADTWIN_BENCH_MPI
#include <mpi.h>

#include <memory>

#include "thermal/mpi/mpi_communicator.hpp"
#endif

#include "bench/bench_common.hpp"
#include "scenarios/input/scenario.hpp"
#include "scenarios/run.hpp"
#include "scenarios/variant_stages.hpp"
#include "sim/deposit.hpp"
#include "thermal/heat.hpp"
#include "thermal/mesh.hpp"

using namespace beadtwin;

namespace {
using bench::seconds_since;

// THERMAL_BENCH_KINDS (above).
void print_kinds(const thermal::ThermalMesh& mesh, const thermal::HeatResult& h) {
  constexpr const char* kNames[4] = {"on top of the layer below", "on top of another", "beside, same layer",
                                     "beside another"};
  double area[4] = {}, cold[4] = {}, healing[4] = {}, substrate[4] = {}, total = 0.0;
  constexpr int kBins = 20;
  double bin_area[kBins] = {}, bin_healing[kBins] = {};
  double open_area[2] = {}, open_healing[2] = {}, open_substrate[2] = {}, open_cold[2] = {};
  for (const thermal::InterfaceResult& r : h.interfaces) {
    const int older = mesh.cells[r.older].layer, younger = mesh.cells[r.younger].layer;
    const int kind = r.on_top ? (younger == older + 1 ? 0 : 1) : (younger == older ? 2 : 3);
    area[kind] += r.area_mm2;
    cold[kind] += r.verdict == thermal::Verdict::kTooCold ? r.area_mm2 : 0.0;
    healing[kind] += r.healing * r.area_mm2;
    substrate[kind] += r.substrate_c * r.area_mm2;
    total += r.area_mm2;
    if (kind == 0 && older >= 12) {
      const bool open = mesh.cells[r.older].open_area_mm2 > 0.0 || mesh.cells[r.younger].open_area_mm2 > 0.0;
      open_area[open] += r.area_mm2;
      open_healing[open] += r.healing * r.area_mm2;
      open_substrate[open] += r.substrate_c * r.area_mm2;
      open_cold[open] += r.verdict == thermal::Verdict::kTooCold ? r.area_mm2 : 0.0;
      const int bin = std::clamp(static_cast<int>(std::floor((r.substrate_c - 110.0) / 5.0)), 0, kBins - 1);
      bin_area[bin] += r.area_mm2;
      bin_healing[bin] += r.healing * r.area_mm2;
    }
  }
  for (int k = 0; k < 4; ++k)
    if (area[k] > 0.0)
      std::printf("interfaces %-26s: area %.3f, too cold %.3f of them, healing %.3f, substrate %.1f C\n",
                  kNames[k], area[k] / total, cold[k] / area[k], healing[k] / area[k],
                  substrate[k] / area[k]);
  for (int b = 0; b < kBins; ++b)
    if (bin_area[b] > 0.0)
      std::printf("  on the layer below, substrate %d-%d C: area %.4f, healing %.3f\n", 110 + 5 * b,
                  115 + 5 * b, bin_area[b] / total, bin_healing[b] / bin_area[b]);
  for (int open = 0; open < 2; ++open)
    if (open_area[open] > 0.0)
      std::printf(
          "  on the layer below, %s: area %.3f, too cold %.3f of them, healing %.3f, substrate %.1f C\n",
          open ? "a cell with open surface" : "no open surface", open_area[open] / total,
          open_cold[open] / open_area[open], open_healing[open] / open_area[open],
          open_substrate[open] / open_area[open]);
  double between = 0.0, between_up = 0.0, same = 0.0, same_up = 0.0;
  for (const thermal::InterfaceResult& r : h.interfaces) {
    const int older = mesh.cells[r.older].layer, younger = mesh.cells[r.younger].layer;
    if (older < 20 || younger > 40) continue;
    if (younger == older + 1) {
      between += r.area_mm2;
      between_up += r.on_top ? r.area_mm2 : 0.0;
    } else if (younger == older) {
      same += r.area_mm2;
      same_up += r.on_top ? r.area_mm2 : 0.0;
    }
  }
  std::printf(
      "layers 20-40: contact between layers %.3g mm2 (%.3g on top), within a layer %.3g mm2 (%.3g "
      "on top)\n",
      between, between_up, same, same_up);
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 5 || argc == 4) {
    std::fprintf(stderr, "usage: thermal_bench SCENARIO [BIRTH_INTERVAL_S [REL_TOL ABS_TOL_K]]\n");
    return 2;
  }
#ifdef BEADTWIN_BENCH_MPI
  MPI_Init(&argc, &argv);
  std::unique_ptr<thermal::Communicator> world = thermal::world_communicator();
  if (world->rank() != 0 && std::freopen("/dev/null", "w", stdout) == nullptr) return 3;
#endif
  std::size_t threads = 0;
  if (const char* t = std::getenv("THERMAL_BENCH_THREADS")) threads = std::strtoul(t, nullptr, 10);
  const tbb::global_control limit(
      tbb::global_control::max_allowed_parallelism,
      threads > 0 ? threads
                  : tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  try {
    openvdb::initialize();
    const scenarios::Scenario sc = scenarios::load_scenario(argv[1]);
    const scenarios::Variant& v = sc.variants.front();
    const Toolpath tp = scenarios::variant_toolpath(v);
    auto t0 = std::chrono::steady_clock::now();
    sim::DepositOptions deposit_options = scenarios::deposit_options(v);
    if (const char* voxel = std::getenv("THERMAL_BENCH_VOXEL"))
      deposit_options.voxel_size_mm = std::atof(voxel);
    const sim::Deposit d = sim::deposit(tp, deposit_options);
    std::printf("deposit %.2f s, %zu voxels\n", seconds_since(t0), d.active_voxels);
    t0 = std::chrono::steady_clock::now();
    // The cells through and across a bead: THERMAL_BENCH_CELLS="THROUGH ACROSS" (else the variant's).
    thermal::MeshOptions mesh_options = scenarios::thermal_mesh_options(v);
    if (const char* cells = std::getenv("THERMAL_BENCH_CELLS"))
      if (std::sscanf(cells, "%d %d", &mesh_options.cells_through, &mesh_options.cells_across) != 2)
        throw std::runtime_error("THERMAL_BENCH_CELLS: expected \"THROUGH ACROSS\"");
    const thermal::ThermalMesh mesh = thermal::build_thermal_mesh(tp, d, mesh_options);
    std::size_t interfaces = 0;
    for (const thermal::ThermalLink& l : mesh.links) interfaces += l.interface;
    std::printf("mesh %.2f s, %zu chains, %zu cells, %zu links, %zu interfaces\n", seconds_since(t0),
                mesh.chains, mesh.cells.size(), mesh.links.size(), interfaces);
    thermal::HeatOptions o;
    o.lump = v.thermal.lump;
    // The lumping's settings, to measure what they cost and gain: THERMAL_BENCH_LUMP="DEPTH TOLERANCE_K".
    if (const char* lump = std::getenv("THERMAL_BENCH_LUMP"))
      if (std::sscanf(lump, "%d %lf", &o.lump_depth, &o.lump_tolerance_k) != 2)
        throw std::runtime_error("THERMAL_BENCH_LUMP: expected \"DEPTH TOLERANCE_K\"");
    if (argc >= 3) o.birth_interval_s = std::atof(argv[2]);
    if (argc == 5) {
      o.rel_tol = std::atof(argv[3]);
      o.abs_tol_k = std::atof(argv[4]);
    }
#ifdef BEADTWIN_BENCH_MPI
    o.communicator = world.get();
#endif
    t0 = std::chrono::steady_clock::now();
    const thermal::HeatResult h =
        thermal::solve_heat(mesh, tp.layers.size(), tp.total_time_s(), v.material, v.machine.environment, o);
    const double solve_s = seconds_since(t0);
    std::size_t hot = 0, cold = 0;
    double min_healing = 1.0;
    for (const thermal::InterfaceResult& r : h.interfaces) {
      hot += r.verdict == thermal::Verdict::kTooHot;
      cold += r.verdict == thermal::Verdict::kTooCold;
      min_healing = std::min(min_healing, r.healing);
    }
    if (std::getenv("THERMAL_BENCH_KINDS")) print_kinds(mesh, h);
    const double simulated = h.end_time_s - h.start_time_s;
    std::printf(
        "heat %.2f s on %d rank(s): birth interval %.3f s, %zu events, %ld steps, %ld rhs, %ld gmres "
        "iterations; energy "
        "in %.4g J lost %.4g J stored %.4g J, balance error %.2e\n",
        solve_s, h.ranks, h.birth_interval_s, h.birth_events, h.steps, h.rhs_evaluations, h.linear_iterations,
        h.energy_in_J, h.energy_lost_J, h.energy_stored_J, h.energy_balance_rel_error);
    std::printf("interfaces %zu: too hot %zu, too cold %zu, min healing %.3f\n", h.interfaces.size(), hot,
                cold, min_healing);
    std::printf("lumping %s: %zu events, %zu cells lumped, %zu model cells at the end\n",
                o.lump ? "on" : "off", h.lump_events, h.lumped_cells, h.model_cells);
    // THERMAL_BENCH_DUMP=FILE: every interface's substrate temperature and healing integral, then every
    // cell's final temperature, one per line, to compare two runs (bench/compare_thermal.py).
    if (const char* dump = std::getenv("THERMAL_BENCH_DUMP")) {
      std::FILE* f = std::fopen(dump, "w");
      if (f == nullptr) throw std::runtime_error(std::string("cannot write ") + dump);
      for (const thermal::InterfaceResult& r : h.interfaces)
        std::fprintf(f, "i %.6g %.6g %d\n", r.substrate_c, r.healing_integral, static_cast<int>(r.verdict));
      for (const float t : h.final_temp_c) std::fprintf(f, "c %.6g\n", t);
      for (const auto& layer : h.layer_temp_c)
        for (const float t : layer) std::fprintf(f, "l %.6g\n", t);
      std::fclose(f);
    }
    std::printf("simulated %.0f s (print %.0f s) in %.2f s: real-time factor %.0f (print only %.0f)\n",
                simulated, tp.total_time_s(), solve_s, simulated / solve_s, tp.total_time_s() / solve_s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
#ifdef BEADTWIN_BENCH_MPI
  world.reset();
  MPI_Finalize();
#endif
  return 0;
}
