// The flattened bead's cross-section (docs/physics.md, bead cross-section): after the roller or tamper
// flattens a bead to height h, its section is a rectangle with semicircular sides, A = h (w − h) + π h² / 4,
// so w = A / h + h (1 − π/4). The model conserves A = Q / v (flow over travel speed), never the nozzle's
// area.
#pragma once

namespace beadtwin {

// Area (mm²) of a bead of width w and height h (mm). Precondition: 0 < h <= w.
double bead_area_mm2(double width_mm, double height_mm);
// Width (mm) of a bead of area A (mm²) flattened to height h (mm). Precondition: h > 0, A >= π h²/4.
double bead_width_mm(double area_mm2, double height_mm);

}  // namespace beadtwin
