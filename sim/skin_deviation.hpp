// How far the printed skin strays from the CAD (docs/physics.md, the part against its CAD): the CAD's signed
// distance (sim/cad_field.hpp) at points of the print's surface, positive where the skin lies outside the
// CAD (material to machine off), negative inside it (undercut). The surface's triangles are sampled as the
// CAD's are (sim/triangle_sampling.hpp, at the voxel spacing), each point weighted by the area it stands
// for.
#pragma once

#include <cstddef>
#include <limits>

#include "sim/cad_field.hpp"
#include "sim/nearest_triangles.hpp"

namespace beadtwin::sim {

// Area-weighted over the skin, mm; all 0 (but the area) when no point was measured.
struct SkinDeviation {
  double mean_mm = 0.0, rms_mm = 0.0;
  double min_mm = 0.0, max_mm = 0.0;
  // At the band's edge: the true value is at least that far out.
  bool min_clamped = false, max_clamped = false;
  double area_mm2 = 0.0;  // printed surface measured
  std::size_t samples = 0;
};

// Measures the deviation of `print` (print_surface: the print's surface, mm) from `cad`, sampling it every
// `spacing_mm` (> 0). Points below `lowest_z_mm` are left out (the table's stand-in below the plate, not
// print). `band_mm`: the CAD field's band, for the clamped flags. Deterministic: in fixed blocks of
// triangles, added up in block order, so the sums do not depend on the number of threads.
SkinDeviation measure_skin_deviation(const NearestTriangles& print, const CadField& cad, double spacing_mm,
                                     double band_mm,
                                     double lowest_z_mm = -std::numeric_limits<double>::infinity());

}  // namespace beadtwin::sim
