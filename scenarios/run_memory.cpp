#include "scenarios/run_memory.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <malloc.h>

#include "core/error.hpp"
#include "core/memory.hpp"
#include "scenarios/variant_stages.hpp"
#include "thermal/mesh.hpp"

namespace beadtwin::scenarios {
namespace {

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

// Bytes as a person reads them: "0.18 GB", "3.4 GB".
std::string gigabytes(double bytes) {
  return bytes < 10e9 ? fmt::format("{:.2f} GB", bytes / 1e9) : fmt::format("{:.1f} GB", bytes / 1e9);
}

}  // namespace

double agreed_voxel_size(thermal::Communicator* ranks, double mine) {
  return ranks == nullptr ? mine : ranks->gather_each(mine)[0];
}

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

}  // namespace beadtwin::scenarios
