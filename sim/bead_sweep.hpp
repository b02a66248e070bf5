// The solid one depositing move sweeps, and its rasterisation into voxel coverage fractions (docs/physics.md,
// deposition).
//
// A moving bead is its profile (sim/bead_section.hpp) swept along the move: a point belongs to it when its
// horizontal distance d to the move's segment (its plan projection clamped to the segment) and its height
// z satisfy  max(d − a, 0)² + (z − z_c)² <= r², where a is the core half-width, r the radius and z_c = z_top
// − r with z_top interpolated along the move. Clamping the projection gives a round end in plan view (the
// nozzle's round footprint). Each end may then be cut by a vertical plane:
//  - at a joint with the neighbouring move of a continuous path, by the bisector plane of the corner, so the
//    two beads together are the swept union of the footprint (round outside the corner, mitred inside)
//    with no material counted twice and, for collinear moves, a seamless bead;
//  - at a free end (path start or stop), by the plane square to the move, unless round free ends are asked
//    for (see DepositOptions::round_free_ends).
// A puddle is a move without length: the profile revolved about the vertical axis through its point.
#pragma once

#include <cstddef>
#include <vector>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "sim/bead_section.hpp"

namespace beadtwin::sim {

// One move's swept bead, as rasterize() takes it.
struct BeadSweep {
  Eigen::Vector2d start_xy = Eigen::Vector2d::Zero();  // plan position of the move's start, mm
  Eigen::Vector2d end_xy = Eigen::Vector2d::Zero();    // equal to start_xy for a puddle
  double start_top_mm = 0.0;                           // bead top (z) at the start, mm
  double end_top_mm = 0.0;
  BeadProfile profile;
  // Unit plan normals of the end cuts; zero for none. The bead keeps the points p with
  // (p − start)·start_cut >= 0 and (p − end)·end_cut < 0 (half-open, so neighbours never share a sample).
  Eigen::Vector2d start_cut = Eigen::Vector2d::Zero();
  Eigen::Vector2d end_cut = Eigen::Vector2d::Zero();

  bool is_puddle() const { return start_xy == end_xy; }
  // Voxels of the bounding box the rasteriser visits, for budgeting.
  double bounding_voxels(double voxel_size_mm) const;
};

// One voxel a sweep covers, and how much of it.
struct CoverageCell {
  openvdb::Coord ijk;
  float fraction = 0.0f;  // part of the voxel inside the sweep, (0, 1]
  float along = 0.0f;     // where along the move the voxel lies, 0 (start) .. 1 (end), for its time stamp;
                          // 1 for a puddle (it is complete when its dwell ends)
};

// Appends every voxel the sweep touches, in a fixed order, with its covered fraction: the bead's extent in
// height is exact above each of `supersample`² regular plan samples of the voxel's column (columns wholly
// outside, or deep inside a level bead, are recognised without sampling). Exact heights matter: layers sit
// on voxel boundaries by design, and point-sampling a rounded flank that is centred on a boundary is
// biased by a few per cent of the flank.
// Voxel (i,j,k) spans [i, i+1) · voxel_size_mm along each axis.
void rasterize(const BeadSweep& sweep, double voxel_size_mm, int supersample, std::vector<CoverageCell>& out);

}  // namespace beadtwin::sim
