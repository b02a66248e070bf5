// The printed part against its CAD (docs/physics.md, the part against its CAD): how much stock the print
// leaves for machining, where it falls short of the CAD (undercut), how far its skin strays from the CAD
// and how much material machining takes off. This is the stage's entry; each step is its own algorithm:
//  - the CAD becomes a signed distance (sim/cad_field.hpp, negative inside, mm): a narrow-band grid on the
//    deposit's voxels near its surface, its exact distance to the nearest triangle further out
//    (sim/nearest_triangles.hpp);
//  - the print becomes a surface (sim/print_surface.hpp): the deposit's fill-fraction isosurface at 0.5 (the
//    part as printed, the surface the renderer draws) meshed, after filling the inside of the slits one
//    voxel thin (sim/slits.hpp) and the voids the print closes in (sim/closed_voids.hpp): both porosity,
//    which the deposit reports; their walls are no surface to machine or to measure from. Voids that open
//    to the outside, such as a channel left between passes that reaches the top, stay surface, as do the
//    mouths of slits and the tips of grooves;
//  - the stock over the CAD surface (sim/cad_stock.hpp): at points sampled on the CAD's triangles
//    (sim/triangle_sampling.hpp), the exact distance to the print's surface, positive inside the print; its
//    least and most found between the samples (sim/stock_extremes.hpp);
//  - the deviation of the printed skin (sim/skin_deviation.hpp): the CAD's signed distance at points sampled
//    on the print's surface;
//  - the material outside the CAD (sim/material_outside.hpp): what machining removes.
// The build plate: the table, not the print, forms the faces that stand on it (a box's bottom). Such CAD
// faces are left out (sim/cad_stock.hpp) and the print's bottom is no surface to measure from: the table
// stands in for material below it (sim/print_surface.hpp). Top faces count: stock on top is a real
// machining allowance.
//
// Stocks are measured up to the band (CadCompareOptions::band_mm) either way; a point with no print surface
// within it is reported at the band ("at least"), with a flag; so is a deviation: a point of the skin with
// no CAD surface within the band.
#pragma once

#include <cstddef>
#include <memory>

#include <openvdb/openvdb.h>

#include "sim/cad_field.hpp"
#include "sim/deposit.hpp"

namespace beadtwin::sim {

// How the print is compared with its CAD.
struct CadCompareOptions {
  // Half-width of the CAD's narrow band and the reach of the stock, mm (> 0): stocks and deviations are
  // measured up to this far on either side of a surface. A few bead widths; at most 256 voxels.
  double band_mm = 0.0;
  // The stock the process asks for, mm (the sections' outer stock): the colour map's white point and the
  // reference for below_requested_stock_fraction.
  double requested_stock_mm = 0.0;
  // Distance between samples on the CAD surface, mm; 0: the voxel size.
  double sample_spacing_mm = 0.0;
  // Leave out the CAD faces on the build plate and let the table stand in for material below the print
  // (see above); false measures the part as if it floated, bottom faces and all.
  bool exclude_plate = true;
};

// What the comparison found.
struct CadComparison {
  // Stock over the CAD surface (excluding the plate), mm: the least and the most anywhere on it (to within
  // a hundredth of a voxel; docs/physics.md) and the area-weighted mean.
  double min_stock_mm = 0.0, max_stock_mm = 0.0, mean_stock_mm = 0.0;
  double p05_stock_mm = 0.0, median_stock_mm = 0.0, p95_stock_mm = 0.0;  // area percentiles
  // The extreme is at the edge of the band: the true value is at least that far out (min: that short).
  bool min_stock_clamped = false, max_stock_clamped = false;
  double undercut_fraction = 0.0;  // share of the CAD surface area with stock < 0 (print short of the CAD)
  // Share of the CAD surface area with less stock than requested_stock_mm (what the process asked for).
  double below_requested_stock_fraction = 0.0;
  double cad_area_mm2 = 0.0;    // CAD surface measured
  double plate_area_mm2 = 0.0;  // CAD surface left out as on the plate
  std::size_t cad_samples = 0;
  double plate_z_mm = 0.0;  // bottom of the lowest printed voxel (fill >= 0.5)

  // Deviation of the printed skin from the CAD (plate left out), area-weighted, mm: positive outside the
  // CAD (material to machine off), negative inside it (undercut).
  double deviation_mean_mm = 0.0, deviation_rms_mm = 0.0;
  double deviation_min_mm = 0.0, deviation_max_mm = 0.0;
  bool deviation_min_clamped = false, deviation_max_clamped = false;  // at the band's edge, as for stock
  double skin_area_mm2 = 0.0;                                         // printed surface measured
  std::size_t skin_samples = 0;

  // Material outside the CAD: what machining removes. Fraction of the deposited volume.
  double outside_volume_mm3 = 0.0;
  double machining_waste_fraction = 0.0;

  double band_mm = 0.0;  // as used
  // The CAD's signed distance (CadField), for the deviation colour map (read-only sharing across threads
  // is safe).
  std::shared_ptr<const CadField> cad_distance;
};

// The CAD's half of a comparison: its signed distance for a deposit of `voxel_size_mm` (deposit_transform),
// which needs no deposit and so can be made while the deposit runs. Throws InputError as compare_with_cad
// does for the CAD and the options.
struct CadDistance {
  double voxel_mm = 0.0, band_mm = 0.0;  // what it was made for
  std::shared_ptr<const CadField> field;
};
CadDistance cad_distance(const CadSurface& cad, double voxel_size_mm, const CadCompareOptions& options);

// Compares `deposit` (the printed part: fill >= 0.5) with `cad`. Throws InputError, listing every problem,
// for a deposit without printed voxels, a CAD without triangles, a vertex that is not finite, a triangle
// index out of range, options out of range, or a CAD so large for the voxels that its bands would not fit
// in memory. Deterministic: the numbers do not depend on the number of threads. `made_ahead`: the CAD's
// distance from cad_distance for the same CAD and options, used when it was made for the deposit's voxels
// and the options' band (else made again here).
CadComparison compare_with_cad(const Deposit& deposit, const CadSurface& cad,
                               const CadCompareOptions& options, const CadDistance* made_ahead = nullptr);

}  // namespace beadtwin::sim
