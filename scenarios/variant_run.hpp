// What one variant's run has made by the time its pictures and report are drawn: internal to the runner
// (run.cpp) and the pictures (pictures.cpp).
#pragma once

#include <algorithm>
#include <limits>
#include <vector>

#include "scenarios/input/scenario.hpp"
#include "sim/cad_compare.hpp"

namespace beadtwin::scenarios {

// What the sections ask of the part against its CAD: the stock to leave (the least over the sections that
// slice the part; infinite when none does), the widest bead, and the deviation map's half range, a layer
// height (a bead's scallop spans half of it; the largest over those sections).
struct StockScale {
  double requested_mm = std::numeric_limits<double>::infinity();
  double widest_bead_mm = 0.0;
  double half_range_mm = 0.0;
};
inline StockScale stock_scale(const Variant& v) {
  StockScale s;
  for (const slicer::SectionParams& section : v.sections) {
    if (!section.outline_path.empty()) continue;  // an AM Outline prints a path, not the part
    s.requested_mm = std::min(s.requested_mm, section.outer_stock_mm);
    s.widest_bead_mm = std::max(s.widest_bead_mm, section.bead_width_mm);
    s.half_range_mm = std::max(s.half_range_mm, section.layer_height_mm);
  }
  return s;
}

// The part against its CAD: what the comparison needs of the sections, and what it found.
struct CadCheck {
  sim::CadComparison comparison;
  double requested_stock_mm = 0.0;
  double map_half_range_mm = 0.0;  // the deviation map's half range: a layer height
};

}  // namespace beadtwin::scenarios
