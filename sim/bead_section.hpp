// The cross-section a depositing move lays (docs/physics.md, bead cross-section), in the form the sweep
// needs.
//
// Every bead profile here is the set of points within `radius_mm` of a horizontal core segment of
// half-width `core_half_width_mm`, whose centre lies `radius_mm` below the bead's top (the roller):
//  - a flattened bead is a stadium of height h and width w: core half-width (w − h)/2, radius h/2;
//  - a bead too thin to reach the roller at full height (A < π h²/4) is round: core 0, radius √(A/π), its top
//    still at the roller, so it is thinner than the layer;
//  - a puddle (a dwell that extrudes, or a print move that does not move) is that profile revolved about the
//    vertical axis through the point: a disc of height h with a rounded rim, or a sphere when even the
//    smallest rimmed disc would hold more than the puddle.
#pragma once

namespace beadtwin::sim {

// A bead's cross-section: a core segment and the radius around it.
struct BeadProfile {
  double core_half_width_mm = 0.0;  // half-width of the flat part of the bead, >= 0
  double radius_mm = 0.0;           // radius of the rounded sides; half the bead's height, > 0

  double width_mm() const { return 2.0 * (core_half_width_mm + radius_mm); }
  double height_mm() const { return 2.0 * radius_mm; }
  // Cross-section area, mm².
  double area_mm2() const;
  // Volume of the profile revolved about the vertical axis through the core's centre (a puddle), mm³.
  double revolved_volume_mm3() const;
};

// Profile of a moving bead of cross-section `area_mm2` (> 0) flattened to `height_mm` (> 0).
BeadProfile moving_bead_profile(double area_mm2, double height_mm);

// Profile whose revolved volume is `volume_mm3` (> 0) at height `height_mm` (> 0): a puddle.
BeadProfile puddle_profile(double volume_mm3, double height_mm);

}  // namespace beadtwin::sim
