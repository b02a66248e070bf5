// Porosity of a deposit: the void fraction inside the printed envelope (docs/physics.md, deposition).
//
// The envelope is found slab by slab (one voxel layer of constant z), in plan:
//  - a voxel at least half full is solid;
//  - a run of less-than-half-full voxels along x or along y, bounded by solid voxels at both ends and at
//    most `max_gap_voxels` long, is an enclosed gap: all of its empty volume is void. Wider openings are
//    taken as intended open space (the inside of a hollow wall, the gap between two parts), not porosity;
//    the caller passes one bead width;
//  - a solid voxel that is not quite full is void for its empty part when all four of its in-plane
//    neighbours are in the envelope (solid or enclosed gap); at the envelope's edge its empty part is the
//    outside air next to the bead's rounded flank.
// porosity = void / (material + void). Its limits: enclosure is judged in plan only (a gap
// open at the top or bottom of its slab still counts), and the under-filled top of an exposed slab whose
// top does not fall on a voxel boundary counts as void.
#pragma once

#include <cstddef>

#include <openvdb/openvdb.h>

namespace beadtwin::sim {

// What measure_porosity found.
struct Porosity {
  double material_voxels = 0.0;  // total fill, in voxel volumes
  double void_voxels = 0.0;      // empty volume inside the envelope, in voxel volumes
  // Faces between a solid voxel (at least half full) and one that is not: the part's surface, inside (voids,
  // gaps) and out, in voxel faces. The fill's iso-surface at one half, meshed at adaptivity 0, has one quad
  // for each; what is meshed from the deposit (the pictures' surfaces, the skin) grows with it.
  std::size_t surface_faces = 0;
  double fraction() const {
    const double envelope = material_voxels + void_voxels;
    return envelope > 0.0 ? void_voxels / envelope : 0.0;
  }
};

// Measures the porosity of `fill` (fill fractions), gaps of at most `max_gap_voxels` counting as enclosed.
// Deterministic whatever the number of threads. Precondition: max_gap_voxels >= 1. When `gaps` is given it
// receives the enclosed gap voxels (the runs above), for locating the voids (sim/voids.hpp).
Porosity measure_porosity(const openvdb::FloatGrid& fill, int max_gap_voxels,
                          openvdb::MaskGrid* gaps = nullptr);

// Porosity as a field, for pictures: at every voxel of the envelope (material and enclosed gaps), the void
// fraction of the cube of (2 radius_voxels + 1)^3 voxels around it, void / (material + void), with the void
// of the enclosed gaps as above (a gap voxel's empty part). Zero where the envelope is solid; outside air is
// neither. Same transform as `fill`. Deterministic whatever the number of threads. Precondition:
// radius_voxels >= 1.
openvdb::FloatGrid::Ptr local_porosity(const openvdb::FloatGrid& fill, const openvdb::MaskGrid& gaps,
                                       int radius_voxels);

}  // namespace beadtwin::sim
