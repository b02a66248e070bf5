// Boundary passes and thin walls: the beads that follow a layer's outline.
#pragma once

#include <vector>

#include "slicer/layer_builder.hpp"

namespace beadtwin::slicer {

// Lays the closed boundary passes (passes[k] holds the loops of pass k, 0 = outermost) in the section's
// order and direction, each starting at the section's start point moved by the seam offset.
void lay_boundary(LayerBuilder& b, const SectionParams& s, const std::vector<Polygons>& passes,
                  int layer_in_section);

// One bead down the centre of each thin wall of `region` (patent (50)).
void lay_thin_walls(LayerBuilder& b, const SectionParams& s, const Polygons& region);

}  // namespace beadtwin::slicer
