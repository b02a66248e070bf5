// What lies under a bead about to be laid (docs/physics.md, deposition: substrate following).
//
// The roller (or the nozzle, on a machine without one) sets the top of a bead at the layer's height; its
// bottom is wherever the material below really is. measure_substrate looks at the deposit, as it stands
// before the bead's layer is laid, in every voxel column under the bead's footprint:
//  - the gap: empty space in the band one layer height deep under the bead's nominal bottom (its top less
//    its layer height), voxel by voxel, down from the bottom until a (nearly) full voxel seals what lies
//    deeper. An under-filled layer below leaves gaps between its beads; the new
//    bead, pressed down by the roller, runs into them first, and what is left of its material makes a
//    narrower bead in its own layer: taller, for the same material.
//  - the material above: what already stands above the nominal bottom. An over-filled layer below
//    leaves less room; the bead comes out flatter and wider, and where the material below reaches the
//    roller the roller ploughs through it.
//  - the material over the top: what stands above the bead's top, up to `reach_mm` above it (a layer
//    height, or the roller's radius), where the roller and the nozzle pass: they run into it.
//  - support: whether a column has material, or the table, within the band; a bead over nothing spans
//    unsupported.
// Below `table_z_mm` (the build table) everything counts as solid. Each measure is the mean over the
// footprint's columns, as a depth in mm. A column is a voxel column whose centre lies within the bead's
// nominal half-width of the bead's centre line (at least the column under the centre line's middle).
#pragma once

#include <limits>
#include <vector>

#include <openvdb/openvdb.h>

#include "sim/bead_sweep.hpp"

namespace beadtwin::sim {

// What measure_substrate found in the voxel columns of a bead piece.
struct Substrate {
  double gap_mm = 0.0;       // mean empty depth in the band below the nominal bottom
  double above_mm = 0.0;     // mean depth of material between the nominal bottom and top
  double over_top_mm = 0.0;  // mean depth of material within `reach_mm` above the top
  double supported = 1.0;    // fraction of the columns with material or the table within the band, 0..1
  int columns = 0;           // columns measured
  // The empty voxels of the band (fraction: the empty part of each, (0, 1]), in a fixed order.
  std::vector<CoverageCell> gap_cells;
};

// Measures what lies under and over one piece of a bead. `sweep`: the piece with its nominal (flattened to
// the layer height) profile; `top_mm`, `height_mm`: its nominal top and layer height at the middle. Reads
// `fill` only (thread-safe while nobody writes it). Voxel (i,j,k) spans [i, i+1) · voxel_size_mm along each
// axis. `highest_k`: no voxel above this index holds material (FillWriter::highest_k), so the columns are not
// read above it; the default reads them all.
Substrate measure_substrate(const BeadSweep& sweep, double top_mm, double height_mm, double reach_mm,
                            const openvdb::FloatGrid& fill, double voxel_size_mm, double table_z_mm,
                            int highest_k = std::numeric_limits<int>::max() - 1);

}  // namespace beadtwin::sim
