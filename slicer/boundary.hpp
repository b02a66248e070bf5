// Boundary passes and thin walls: the beads that follow a layer's outline.
#pragma once

#include <vector>

#include "slicer/centre_beads.hpp"
#include "slicer/fill.hpp"
#include "slicer/layer_builder.hpp"

namespace beadtwin::slicer {

// A layer's boundary passes and the region left for its fill.
struct BoundaryPlan {
  std::vector<Polygons> loops;                // closed loops of pass k (0 = outermost)
  std::vector<std::vector<Polyline>> pieces;  // open pieces of pass k that end against a shared wall
  FillRegions fill;                           // where the fill goes (empty centres: no fill)
  Polygons reach;                             // what the outermost pass's beads can cover
};

// Pass k runs along the outline offset inward by w/2 + k·pitch (pitch = w·(1 − overlap)). Where two sides
// of one pass would overlap more than the maximum pass overlap, the pass is left out there. With a
// `shared_wall` (the neighbouring section's region at this height, patent (17)), the passes run as if the
// two sections were one and stop `overlap·w` inside the neighbour, whose wall stands in for this one's.
BoundaryPlan plan_boundary(const SectionParams& s, const Polygons& region, const Polygons& shared_wall,
                           bool fill);

// Lays the passes in the section's order and direction: closed loops start at the section's start point
// moved by the seam offset; open pieces start at the end nearer the start point.
void lay_boundary(LayerBuilder& b, const SectionParams& s, const BoundaryPlan& plan, int layer_in_section);

// One bead down the centre of each thin wall of `region` (patent (50)): the parts the outermost pass
// cannot reach.
void lay_thin_walls(LayerBuilder& b, const SectionParams& s, const Polygons& region,
                    const BoundaryPlan& plan);

// The thin-wall parameters of a section as rules for centre-line beads.
CentreBeadRules thin_wall_rules(const SectionParams& s);

}  // namespace beadtwin::slicer
