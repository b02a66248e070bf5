// Voids located: the enclosed gaps the porosity measure finds (sim/porosity.hpp), joined
// into connected pieces, each reported where it is, in which layer, beside which beads, and what kind of
// gap it is by the beads around it:
//  - "at a zigzag turn": beside two consecutive moves of one path that turn by more than 90° (the corner
//    of a zigzag fill, or of a boundary, that the bead's round end leaves open);
//  - "between fill and boundary": beside a fill bead and a boundary pass;
//  - "between passes": beside boundary passes only;
//  - "between fill beads": beside fill beads only;
//  - "between beads" otherwise.
#pragma once

#include <vector>

#include <openvdb/openvdb.h>

#include "core/toolpath.hpp"
#include "sim/deposit.hpp"

namespace beadtwin::sim {

// What locate_voids found.
struct VoidsFound {
  std::vector<Defect> defects;           // the largest voids first, at most `max_listed`
  std::size_t count = 0;                 // every void of at least `min_volume_mm3`
  std::vector<double> layer_volume_mm3;  // void volume by the layer it lies in (parallel to Toolpath::layers)
};

// Joins the gap voxels into voids, each listed as a defect. `gaps`: the enclosed gap voxels; `fill`, `layer`,
// `move`: the deposit's grids. Voids smaller than `min_volume_mm3` count in the layers' volumes but are not
// listed. Deterministic.
VoidsFound locate_voids(const openvdb::MaskGrid& gaps, const Deposit& deposit, const Toolpath& toolpath,
                        double min_volume_mm3, std::size_t max_listed);

}  // namespace beadtwin::sim
