// The stock over the CAD's surface (docs/physics.md, the part against its CAD): how much material the print
// leaves for machining at each point of the CAD, or how far it falls short of it.
//
// The stock at a point of the CAD surface is its exact distance to the print's surface (the nearest of its
// triangles, sim/nearest_triangles.hpp), positive where the point lies inside the print, negative outside:
// the radius of the ball of material around the point (positive: material to machine off in every
// direction) or how far the point lies outside the print (undercut). It is the nearest-distance allowance a
// machinist means: at a convex corner it is the distance to the print's nearest surface, not along any one
// normal. The CAD surface is sampled deterministically (sim/triangle_sampling.hpp), each sample weighted by
// the area it stands for; the least and the most stock are then found between the samples
// (sim/stock_extremes.hpp).
//
// The build plate: a CAD face is on the plate where it faces down (its outward normal within about 25° of
// straight down) and lies within one voxel above the plate (the bottom of the lowest printed voxel). The
// table, not the print, forms such faces (a box's bottom): their area is counted apart and their stock left
// out. Top faces count: stock on top is a real machining allowance.
#pragma once

#include <cstddef>
#include <vector>

#include <openvdb/openvdb.h>

#include "sim/cad_field.hpp"
#include "sim/nearest_triangles.hpp"
#include "sim/stock_extremes.hpp"

namespace beadtwin::sim {

// Lengths of the comparison, mm.
struct StockGeometry {
  double voxel_mm = 0.0;    // the deposit's voxel size
  double spacing_mm = 0.0;  // between samples on the CAD surface
  double band_mm = 0.0;     // the reach of the stock: no stock is measured beyond ±band_mm
};

// The CAD's triangles with area (`cad` checked as compare_with_cad checks it), each with its samples' place
// in the list of all samples at `spacing_mm`. Throws InputError when they would take more than `max_samples`.
std::vector<SampledTriangle> cad_triangles(const CadSurface& cad, double spacing_mm, std::size_t max_samples);

// Marks the triangles that may stand on the plate at `plate_z_mm`: facing down (outward by `cad_distance`,
// the CAD's signed distance grid, whatever the winding) and reaching within a voxel of `voxel_mm` above it.
void mark_plate(std::vector<SampledTriangle>& triangles, const openvdb::FloatGrid& cad_distance,
                double voxel_mm, double plate_z_mm);

// The stock over the CAD surface, the samples on the plate left out.
struct StockStats {
  // The least and the most anywhere (to within a hundredth of a voxel), and the area-weighted mean, mm.
  double least_mm = 0.0, most_mm = 0.0, mean_mm = 0.0;
  double p05_mm = 0.0, median_mm = 0.0, p95_mm = 0.0;  // area percentiles, mm
  // The extreme is at the edge of the band: the true value is at least that far out (least: that short).
  bool least_clamped = false, most_clamped = false;
  double undercut_fraction = 0.0;         // share of the area with stock < 0
  double below_requested_fraction = 0.0;  // share of the area with less stock than requested
  double area_mm2 = 0.0;                  // measured
  double plate_area_mm2 = 0.0;            // left out as on the plate
  std::size_t samples = 0;                // measured
};

// Measures the stock of every sample of `triangles` (cad_triangles, mark_plate) against `print`, the print's
// surface (print_surface), telling inside from outside beyond the band by `solid` (solid_print, fill
// fractions). `requested_stock_mm`: the stock asked for; `plate_z_mm`: the plate's height. Throws InputError
// when every sample lies on the plate. Deterministic: the numbers do not depend on the number of threads.
StockStats measure_stock(const std::vector<SampledTriangle>& triangles, const NearestTriangles& print,
                         const openvdb::FloatGrid& solid, const StockGeometry& g, double requested_stock_mm,
                         double plate_z_mm);

}  // namespace beadtwin::sim
