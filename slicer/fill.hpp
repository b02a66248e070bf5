// Fill: the beads that cover the region inside a layer's boundary passes.
#pragma once

#include "slicer/layer_builder.hpp"

namespace beadtwin::slicer {

// Zigzag fill of `fill_region` (the region the fill beads' centres may reach), at the section's fill angle
// turned by `layer_in_section` steps.
void lay_fill(LayerBuilder& b, const SectionParams& s, const Polygons& fill_region, int layer_in_section);

}  // namespace beadtwin::slicer
