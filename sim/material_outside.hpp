// The material outside the CAD: what machining removes (docs/physics.md, the part against its CAD). Each
// voxel's material times the share of the voxel outside the CAD, 1/2 + d/s clamped to 0..1 (d the CAD's
// signed distance at the voxel's centre, s the voxel size): exact for a plane parallel to a voxel face
// through the voxel, and unbiased for any plane on average.
#pragma once

#include <openvdb/openvdb.h>

namespace beadtwin::sim {

// What measure_material_outside found.
struct MaterialOutside {
  double volume_mm3 = 0.0;  // outside the CAD
  double fraction = 0.0;    // of all the material (0 without material)
};

// `fill`: fill fractions (0..1) on voxels of `voxel_mm`; `cad_distance`: the CAD's signed distance (mm,
// negative inside) on the same voxels (CadField::grid: ±its band beyond it). Deterministic: the sums do not
// depend on the number of threads.
MaterialOutside measure_material_outside(const openvdb::FloatGrid& fill,
                                         const openvdb::FloatGrid& cad_distance, double voxel_mm);

}  // namespace beadtwin::sim
