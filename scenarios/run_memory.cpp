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

// The rest of what the later stages build: the pictures' frames, the CAD's scene.
constexpr double kLaterFixedBytes = 100e6;
// What the run holds of its program: the program's own, and the moves with their motion plan and what the
// reader kept, per byte of moves.
constexpr double kHeldFixedBytes = 60e6;
constexpr double kHeldPerMoveByte = 2.1;
// Before the deposit, what the stages after it build from it while it is held (the CAD comparison's distance
// grids, the thermal cell grid and mesh, the rendered surface), per byte of its grids. Measured
// (docs/RELIABILITY.md): the whole run's peak is 2.4 times the deposit's own on the default scenario, 3.3
// times on the LSAM hull mould and at least 2.7 times on a 156 MB PrusaSlicer program; the deposit and these
// together are counted as 3.5 times the deposit.
constexpr double kLaterBytesPerDepositByte = 2.5;

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
    // The deposit found too large is gone: what it freed goes back to the system, not left to the allocator,
    // which would otherwise raise the peak of the deposit after it (docs/RELIABILITY.md).
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
  return program.bytes() + deposit.bytes() + rest.bytes() + thermal.bytes() + surfaces.bytes();
}

double RunMemory::in_turn() const {
  return program.bytes() + deposit.bytes() + rest.bytes() + std::max(thermal.bytes(), surfaces.bytes());
}

RunMemory RunMemory::at_voxel_ratio(double r) const {
  return {program.at_voxel_ratio(r),  deposit.at_voxel_ratio(r), thermal.at_voxel_ratio(r),
          surfaces.at_voxel_ratio(r), rest.at_voxel_ratio(r),    budget};
}

double RunMemory::least() const {
  return (program + deposit + rest + thermal + surfaces).fixed_bytes;
}

double RunMemory::fitting_voxel_mm(double voxel_mm) const {
  return beadtwin::fitting_voxel_mm(voxel_mm, budget, least(), [&](double size_mm) {
    return at_voxel_ratio(voxel_mm / size_mm).in_turn();
  });
}

RunMemory run_memory(const Variant& v, const Toolpath& tp, const sim::Deposit& d) {
  RunMemory m;
  m.program.fixed_bytes =
      kHeldFixedBytes + kHeldPerMoveByte * static_cast<double>(tp.moves.size() * sizeof(Move));
  m.deposit = sim::deposit_cost(d);
  m.thermal = thermal::thermal_cost(tp, d, thermal_mesh_options(v));
  m.surfaces = sim::surface_cost(d);
  m.rest.fixed_bytes = kLaterFixedBytes;
  m.budget = memory_budget_bytes(v.output.memory_budget_gb * 1e9);
  return m;
}

double later_bytes_per_deposit_byte() {
  return kLaterBytesPerDepositByte;
}

}  // namespace beadtwin::scenarios
