// Fill: the beads that cover the region inside a layer's boundary passes, in the section's fill style
// (patent (56)-(65)).
#pragma once

#include "slicer/fill_styles.hpp"
#include "slicer/layer_builder.hpp"

namespace beadtwin::slicer {

// Where a layer's fill goes: the region its bead centres may reach (the passes' sides overlap the boundary
// beads by the boundary side overlap), and how far the free ends of its passes run on past that region
// (into the boundary beads by the boundary overlap).
struct FillRegions {
  Polygons centres;
  double end_reach_mm = 0.0;
};

// The fill regions inside `passes_laid` boundary passes of the region `host`.
FillRegions fill_regions(const SectionParams& s, const Polygons& host, int passes_laid);

// Lays the fill of `regions` in the section's style, at its fill angle turned by `layer_in_section` steps.
// `solid` keeps a sparse style solid (a top or bottom surface layer). Returns the beads laid.
int lay_fill(LayerBuilder& b, const SectionParams& s, const FillRegions& regions, int layer_in_section,
             bool solid);

}  // namespace beadtwin::slicer
