// Beads down centre lines: thin walls too narrow for the boundary passes (patent (50)) and voids the
// slicer finds (patent (46)) are filled by beads that follow their medial axis, as wide as they are.
#pragma once

#include <vector>

#include "slicer/layer_builder.hpp"
#include "slicer/medial_axis.hpp"

namespace beadtwin::slicer {

// How centre lines become beads (the thin-wall parameters of patent (50)).
struct CentreBeadRules {
  double min_width_mm = 0.0;       // thinner parts get no bead
  double max_width_mm = 0.0;       // wider parts get no bead (they are not thin)
  double one_bead_width_mm = 0.0;  // wider than this: two beads side by side, each half as wide
  // A bead keeps one width while the part's thickness stays within this of it (0: follows it point by
  // point).
  double thickness_deviation_mm = 0.0;
  double stitching_gap_mm = 0.0;          // line ends closer than this are joined into one bead
  double intersection_distance_mm = 0.0;  // free ends reach on this far to meet `meet`
};

// A bead path: points and the bead width of each segment (widths.size() == points.size() − 1).
struct CentreBead {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> widths_mm;
};

// The bead paths for the centre lines of `pieces`. Free ends (not at a junction) run on by half their width
// to the end of the piece (the medial axis stops that short of a square end), and on up to the
// intersection distance further while that brings them to `meet` (the area the passes cover).
std::vector<CentreBead> centre_beads(const Polygons& pieces, const Polygons& meet,
                                     const CentreBeadRules& rules);

// Lays `beads` (melt on, the segments with their widths, melt off); returns how many were laid.
int lay_centre_beads(LayerBuilder& b, const std::vector<CentreBead>& beads, Feature feature);

}  // namespace beadtwin::slicer
