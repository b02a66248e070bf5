// The memory a variant's run needs once its deposit is made, against the memory budget, and the deposit
// made to fit it (docs/RELIABILITY.md).
#pragma once

#include <functional>

#include "core/memory.hpp"
#include "core/toolpath.hpp"
#include "scenarios/input/scenario.hpp"
#include "sim/deposit.hpp"
#include "thermal/communicator.hpp"

namespace beadtwin::scenarios {

// The memory the rest of a run needs once its deposit is made, against the budget (docs/RELIABILITY.md). The
// estimate made before the deposit goes by the material's volume; a part that is mostly surface (a desktop
// print's thin infill walls) needs far more for what is meshed from it than a part of the same volume that
// is mostly solid. Once the deposit is made its surface is known. Each stage declares its own cost, from
// what it grows with (measured), so that the same input on the same machine gets the same answer; this adds
// them:
//  - what the run holds: the moves with their motion plan, and the deposit's grids (sim::deposit_cost);
//  - the thermal stage: its cells and its grid of the cell each voxel is in (thermal::thermal_cost);
//  - what is meshed from the surface (sim::surface_cost);
//  - a fixed allowance for the rest (the pictures' frames, the CAD's scene).
// Side by side the pictures' surfaces and scenes are held through the thermal stage; in turn they are built
// after it, and the peak is the larger of the two.
struct RunMemory {
  MemoryCost program;   // held: the moves with their motion plan, and the program's own
  MemoryCost deposit;   // held: the deposit's grids and what its work left to the allocator
  MemoryCost thermal;   // the thermal cells and the grid of the cell each voxel is in
  MemoryCost surfaces;  // what is meshed from the surface
  MemoryCost rest;      // the pictures' frames, the CAD's scene
  double budget = 0.0;  // output.memory_budget, or three quarters of the machine's memory, bytes
  // The run's peak, bytes, with the pictures' surfaces beside the thermal stage or after it.
  double side_by_side() const;
  double in_turn() const;
  // The same at voxels 1/r times as large (MemoryCost::at_voxel_ratio).
  RunMemory at_voxel_ratio(double r) const;
  // What the run needs at any voxel size: the program, the thermal cells and what every run holds, bytes.
  double least() const;
  // The smallest voxel size in tenths of a millimetre above `voxel_mm` (this estimate's) at which the run
  // fits in turn, with a tenth of the budget to spare; 0 when none would: the program and the thermal
  // cells alone take it.
  double fitting_voxel_mm(double voxel_mm) const;
};
// The estimate for `variant` printing `toolpath` into `deposit`.
RunMemory run_memory(const Variant& variant, const Toolpath& toolpath, const sim::Deposit& deposit);

// What the stages after the deposit build from it while it is held, bytes per byte of the deposit's grids:
// the run's share of the estimate made before the deposit
// (sim::DepositOptions::later_bytes_per_deposit_byte).
double later_bytes_per_deposit_byte();

// Deposits the variant's toolpath and checks that the rest of the run fits the memory budget once the
// deposit's surface is known (RunMemory). Over it, a voxel size the scenario set is an error naming one that
// would fit; an automatic one is made coarser and the toolpath deposited again, with a note. `progress` may
// be empty; `need` receives the estimate for the deposit returned. Under mpirun (`ranks` not null) the other
// ranks deposit at the size settled on here (agreed_voxel_size).
sim::Deposit deposit_within_budget(const Variant& variant, const Toolpath& toolpath,
                                   const std::function<void(double)>& progress, thermal::Communicator* ranks,
                                   RunMemory& need);

// Under mpirun, the voxel size every rank deposits a variant at: rank 0's, said once its deposit is known to
// fit the memory budget (0: it stopped on that). Every rank calls it once after each variant's deposit.
// Alone (`ranks` null): `mine`.
double agreed_voxel_size(thermal::Communicator* ranks, double mine);

}  // namespace beadtwin::scenarios
