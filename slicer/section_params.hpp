// A section's print parameters (the Thermwood patent's sectioned slicing, paragraphs (41)-(65)) and their
// declaration: every key a scenario's section takes, with its unit, default, range, meaning and source, bound
// to the member of SectionParams it sets (core/param.hpp). The scenario reader reads sections through the
// declaration, and the planner checks a section's values against the same ranges before it plans.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/enum_names.hpp"
#include "core/melt_settings.hpp"
#include "core/param.hpp"
#include "slicer/mesh.hpp"
#include "slicer/polygons.hpp"

namespace beadtwin::slicer {

// Boundary passes (patent (49)-(50)): the beads laid along each contour of a layer.
struct BoundaryParams {
  int passes = 1;         // beads laid along each contour, outermost first (patent (49))
  double overlap = 0.10;  // least overlap between neighbouring passes, fraction of the bead width
  // Most that two passes may overlap (patent (50)): where passes offset from opposite sides of a narrow part
  // would overlap more, the inner one is left out there (its narrow remainder is a thin wall).
  double max_overlap = 1.0;
  bool inside_out = false;         // lay the innermost pass first (patent (49))
  bool reverse_alternate = false;  // run every other layer's passes the opposite way round (patent (49))
  double lead_in_mm = 0.0;         // bead laid on a straight approach before each pass starts (patent (50))
  // Bead laid on a straight run-off after each pass ends, tangent to its end (patent (50)).
  double lead_out_mm = 0.0;
  // Lead-out straight on along the pass's last direction (true), or on along the pass itself (false).
  bool tangential_lead_out = true;
  double start_stop_overlap =
      0.0;  // a closed pass runs on past its start by this fraction of w (patent (50))
  double min_pass_length_mm = 0.0;
  // Thin walls (patent (50)): parts of the outline too narrow for the passes (a bead's centre cannot reach
  // them), no wider than thin_wall_max_width_mm (0: the bead width), are filled down their centre lines.
  bool thin_walls = false;
  double thin_wall_max_width_mm = 0.0;
  // Walls up to this width (0: the bead width) get one bead of the wall's own width; wider ones get two
  // beads side by side.
  double thin_wall_one_bead_width_mm = 0.0;
  // A centre line's bead keeps one width while the wall's thickness stays within this of it; where the
  // thickness strays further, a new bead width starts (0: the bead width follows the wall point by point).
  double thin_wall_thickness_deviation_mm = 0.0;
  // Centre-line pieces whose ends are closer than this are stitched into one bead.
  double thin_wall_stitching_gap_mm = 0.0;
  // Centre lines that end closer than this to a pass are extended to meet it.
  double thin_wall_intersection_distance_mm = 0.0;
};

// The fill styles of patent (56)-(62), FIGS. 15-19.
enum class FillStyleKind : std::uint8_t {
  kOneWay,                      // FIG. 15: every line the same way, back to the start side between lines
  kSimpleZigzag,                // FIG. 16: serpentine; over a hole it stops depositing, crosses, resumes
  kSmartZigzag,                 // FIG. 17: serpentine that never crosses a hole (cell by cell)
  kSmartZigzagConstantOverlap,  // FIG. 18: smart zigzag with one overlap throughout each cell
  kSparseZigzag,                // FIG. 19: a serpentine with gaps, then serpentines that fill the gaps
  kVariableBeadRegions,         // (62): smart zigzag, then beads down the voids left against the boundary
};

inline constexpr EnumName<FillStyleKind> kFillStyleNames[] = {
    {FillStyleKind::kOneWay, "one_way"},
    {FillStyleKind::kSimpleZigzag, "simple_zigzag"},
    {FillStyleKind::kSmartZigzag, "smart_zigzag"},
    {FillStyleKind::kSmartZigzagConstantOverlap, "smart_zigzag_constant_overlap"},
    {FillStyleKind::kSparseZigzag, "sparse_zigzag"},
    {FillStyleKind::kVariableBeadRegions, "variable_bead_regions"}};
constexpr std::span<const EnumName<FillStyleKind>> enum_names(FillStyleKind) {
  return kFillStyleNames;
}
// The style's name in scenarios and reports ("smart_zigzag").
inline std::string_view to_string(FillStyleKind style) {
  return name_of(style);
}

// Fill passes (patent (56)-(65)): the beads inside the boundary passes.
struct FillParams {
  bool enabled = false;
  FillStyleKind style = FillStyleKind::kSmartZigzag;
  double angle_deg = 45.0;       // fill direction of the section's first layer (patent (63))
  double angle_step_deg = 90.0;  // change in fill angle from one layer to the next (patent (63))
  double overlap = 0.10;     // least overlap between fill passes, fraction of w (patent (63) pass overlap)
  double max_overlap = 0.5;  // most overlap between fill passes (constant-overlap style)
  double max_sparse_spacing_mm = 0.0;  // sparse zigzag: first serpentine's line spacing (0: twice the pitch)
  bool sparse_fill_gaps = true;  // sparse zigzag: then the passes in its gaps (false: the fill stays sparse)
  double boundary_overlap = 0.10;       // fill line ends reach into the boundary beads by this fraction of w
  double boundary_side_overlap = 0.10;  // fill lines beside the boundary overlap it by this fraction of w
  double max_end_overlap_mm = 0.0;      // caps on those two distances (0: no cap)
  double max_side_overlap_mm = 0.0;
  bool optimize_to_surface = false;  // ends reach as far into the boundary as the caps allow (accuracy first)
  bool link_with_rapids = false;     // every line its own bead: melt off, rapid, melt on between lines
  double min_length_mm = 0.0;        // fill lines shorter than this are left out
  double lead_in_mm = 0.0;           // straight approach printed before each fill bead
  double lead_out_mm = 0.0;          // printed run-off after each fill bead
  bool tangential_lead_out = true;
  // Fill style parameters (patent (64)-(65)).
  double fillet_radius = 0.0;           // turn corners rounded by this fraction of the bead's radius (w/2)
  double corner_melt_reduction = 0.0;   // the pump slows by this fraction on the turns
  double corner_speed_mm_s = 0.0;       // head speed on the turns (0: the fill speed)
  bool turns_outside = false;           // turns may run outside the fill region (into the boundary)
  double line_matching_limit_mm = 0.0;  // a shorter line is extended to meet a longer at a turn up to this
  double line_extension_mm = 0.0;       // lines run on this far past the region before turning
  // A sparse fill that leaves its gaps keeps top and bottom surfaces solid: a layer with part faces within
  // the angle tolerance of horizontal, larger than the step tolerance across, is filled solid.
  double step_tolerance_mm = 0.0;
  double angle_tolerance_deg = 5.0;
};

// Corner pull-back (patent (47)): the roller cannot follow a sharp corner; it lifts this long before the
// corner and the bead runs on past the corner by the extension, so the roller re-engages away from it
// instead of ploughing material out of the corner.
struct PullBackParams {
  double length_mm = 0.0;      // 0: no pull-back
  double extension_mm = 0.0;   // run-on past the corner
  double min_turn_deg = 60.0;  // a corner is a turn at least this sharp
};

// Smoothing (patent (47)); "remove small polygons" is SectionParams::min_polygon_area_mm2.
struct SmoothingParams {
  bool smooth_curves = false;          // simplification keeps curves smooth (no facets the part lacks)
  bool never_start_in_corner = false;  // pass starts move off corners onto a straight run
  double min_polygon_angle_deg = 0.0;  // corners sharper than this (interior angle) are blunted
};

// Void detection (patent (46)): after a layer is planned, the parts of its outline no bead covers.
struct VoidParams {
  bool detect = false;        // find and count them
  bool fill = false;          // and lay a bead down each one wide enough to take one
  double min_width_mm = 0.0;  // narrower voids are left (the roller squeezes them shut); 0: w/4
};

// One section of a part: its Z range or body, and everything its layers are printed with.
struct SectionParams {
  std::string name;
  std::string body;  // slice only this body of the part (patent (12), (35)); empty: the whole part
  // AM Outline (patent (39)): when set, the section prints this 2-D path itself, layer after layer, instead
  // of slicing the part.
  std::vector<Eigen::Vector2d> outline_path;
  bool outline_closed = true;
  // Variable layer height with constant feed (seed 002, eqs. 4-12; AM Outline sections): the bead's height
  // grows by `height_slope` mm per mm along `height_direction` from the path's first point in that
  // direction, its core width w − h staying that of the layer height; the extruder's flow stays constant
  // and the head slows where the bead is taller (eq. 12), and every layer's top follows the wedge.
  double height_slope = 0.0;
  Eigen::Vector2d height_direction = Eigen::Vector2d::UnitX();
  double z_min_mm = 0.0;  // bottom of the section's first layer
  double z_max_mm = 0.0;  // top of the section's last layer
  double layer_height_mm = 0.2 * kMmPerInch;
  double bead_width_mm = 0.83 * kMmPerInch;
  double print_speed_mm_s = 100.0;
  double travel_speed_mm_s = 300.0;
  // Closed passes start at the contour point nearest this point (patent (43) start point location)...
  Eigen::Vector2d start_point_mm = Eigen::Vector2d::Zero();
  // ...moved along the contour by this much more on every layer, so seams do not stack (patent (43)).
  double seam_offset_mm = 0.0;
  double chord_tolerance_mm = 0.0;  // outlines follow the part within this (patent (41)); 0: exactly
  double min_polygon_area_mm2 =
      0.0;  // outline contours smaller than this are left out (patent (47) smoothing)
  // Moves the section's toolpath in the plane, so beads of neighbouring sections overlap where the sections
  // must fuse (patent (15), (67)).
  Eigen::Vector2d shift_mm = Eigen::Vector2d::Zero();
  // Containment boundaries (patent (41)): the section prints only inside the outside boundary (when given)
  // and outside the inside boundaries; their edges become contours of the section's layers.
  Polygons containment_outside, containment_inside;
  // Slice plane (patent (44)): top slices the part as it is modelled; front and side lay it down first, so
  // layers are parallel to its XZ (front) or YZ (side) plane.
  SlicePlane slice_plane = SlicePlane::kTop;
  // A section whose wall this one uses as its own (patent (17)): where this section's outline meets that
  // one's, it lays no wall of its own; its passes end against the other's wall and its fill runs up to it.
  std::string shares_wall_with;
  double contact_offset_mm =
      0.0;  // the section prints this much above (below, negative) its Z limits (patent (45))
  // Toolpath parameters (patent (44)-(45)).
  double outer_stock_mm = 0.0;  // the outline's outer contours grow by this (stock to machine off)
  double inner_stock_mm = 0.0;  // the outline's holes shrink by this
  // Combine stock offset with toolpath offset (patent (45)): one offset of w/2 − stock from the outline
  // (corners stay sharp), instead of the stock envelope first (constant distance, round at convex
  // corners) and the passes offset from it.
  bool combine_stock_offset = false;
  // Arc chord tolerance (patent (45)): the program writer fits G2/G3 arcs within this of the moves.
  double arc_chord_tolerance_mm = 0.0;
  bool merge_slices = false;           // use the largest of the previous, this and the next layer's outline
  bool ignore_inner_contours = false;  // fill holes in: print every outline as solid
  bool fill_first = false;             // layer order: fill before the boundary passes
  double initial_clearance_height_mm = 0.0;  // the head starts the program at this height (0: first layer)
  double clearance_height_mm =
      0.0;  // between layers the head rises to this height above the table (0: no lift)
  // Process parameters (patent (46)).
  double melt_reduction = 0.0;  // pump slows by this fraction where a bead is laid over one just laid
  int rafts = 0;                // layers printed under the section's first layer (the part sits on them)
  int stock_on_top = 0;         // layers printed on the section's top layer with its outline
  MeltSettings melt;            // melt on / melt off (patent (51)-(53))
  PullBackParams pull_back;
  SmoothingParams smoothing;
  VoidParams voids;
  BoundaryParams boundary;
  FillParams fill;
};

// Every parameter of a section, in the order the docs list them.
std::span<const Param<SectionParams>> section_params();

// Throws InputError naming every value of `s` outside its declared range (keys as
// "sections.<name>.<key>").
void check_section_ranges(const SectionParams& s);

}  // namespace beadtwin::slicer
