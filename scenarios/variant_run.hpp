// What one variant's run has made by the time its pictures and report are drawn: internal to the runner
// (run.cpp) and the pictures (pictures.cpp).
#pragma once

#include <vector>

#include "sim/cad_compare.hpp"
#include "thermal/heat.hpp"
#include "thermal/mesh.hpp"
#include "thermal/summary.hpp"

namespace beadtwin::scenarios {

// The thermal model of a variant's deposit and what its interfaces add up to.
struct ThermalRun {
  thermal::ThermalMesh mesh;
  thermal::HeatResult heat;
  std::vector<thermal::FusionSummary> layers;  // parallel to Toolpath::layers
  std::vector<thermal::Verdict> cells;         // per thermal cell, for the fusion map
};

// The part against its CAD: what the comparison needs of the sections, and what it found.
struct CadCheck {
  sim::CadComparison comparison;
  double requested_stock_mm = 0.0;
  double map_half_range_mm = 0.0;  // the deviation map's half range: a layer height
};

}  // namespace beadtwin::scenarios
