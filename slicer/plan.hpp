// Sectioned path planning (the Thermwood patent's sectioned slicing, first cut): the part is divided into
// sections by Z range, each with its own layer height, bead, speed, boundary passes and fill; each section
// is sliced into planar layers; each layer gets its boundary passes (offsets of the outline) and, where
// asked, a zigzag fill whose angle turns from layer to layer; the layers of all sections are merged by Z
// into one Toolpath.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/flow.hpp"
#include "core/melt_settings.hpp"
#include "core/toolpath.hpp"
#include "slicer/mesh.hpp"
#include "slicer/polygons.hpp"

namespace beadtwin::slicer {

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

inline constexpr FillStyleKind kFillStyles[] = {
    FillStyleKind::kOneWay,       FillStyleKind::kSimpleZigzag,
    FillStyleKind::kSmartZigzag,  FillStyleKind::kSmartZigzagConstantOverlap,
    FillStyleKind::kSparseZigzag, FillStyleKind::kVariableBeadRegions};
// The style's name in scenarios and reports ("smart_zigzag").
std::string_view to_string(FillStyleKind style);

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
  double layer_height_mm = 5.08;
  double bead_width_mm = 21.08;
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

struct PlanStats {
  int empty_layers = 0;  // layers whose slice was empty (nothing to print there)
  int open_chains = 0;   // slice loops that did not close (mesh holes), summed over layers
  // Void detection: uncovered pieces wider than the section's minimum void width, before any void fill.
  int voids_found = 0;
  double void_area_mm2 = 0.0;
  int void_beads = 0;  // beads laid in them (void fill)
  // Per section (as plan_toolpath's `sections`): the most boundary passes any of its part's layers (not
  // rafts, not stock on top) had room for. Fewer than asked: the region holds no more (each pass lays a bead
  // along every contour, so a wall between an outer and an inner contour takes two beads a pass).
  std::vector<int> most_passes_laid;
};

// What is wrong with section `s` sharing the wall of the section it names (patent (17)), or empty when
// nothing is: that must be another sliced section laying its layers at the same heights. Sets `provider`
// to its index when given.
std::string shared_wall_problem(const std::vector<SectionParams>& sections, const SectionParams& s,
                                std::size_t* provider = nullptr);

// Plans every section and merges their layers by height into one Toolpath (times from `motion`). Sections
// may overlap in Z only when they slice different bodies (checked by the scenario loader). Throws InputError
// on parameters the planner cannot use. With an `extruder`, each section's melt on / melt off settings
// become prime, coast and reverse events (slicer/melt_events.hpp); without one, sections must not ask for
// them.
Toolpath plan_toolpath(const TriangleMesh& mesh, const std::vector<SectionParams>& sections,
                       const MotionLimits& motion, PlanStats* stats = nullptr,
                       const Extruder* extruder = nullptr);

// The part's CAD as `sections` print it, in the machine frame (mm): what the printed part is measured
// against. A section that slices the whole part contributes the part laid down on its slice plane; one that
// names a body, that body laid down on its own (as the planner slices it). The whole part is taken once, on
// the slice plane of the first section that slices it whole — when sections disagree on the plane, the
// first wins — and then holds every body; otherwise each named body is taken once, from the first section
// naming it. Rafts under the lowest section lift the CAD with the print (the part stands on them); contact
// offsets and in-plane shifts move only the toolpath, so they show as stock or undercut. The whole part is
// taken even where no section's Z range or containment boundary reaches it: what is not printed is undercut.
// AM Outline sections (outline_path set) print their own path, not the part: they add nothing, and when every
// section is one there is no CAD (nullopt). Throws InputError for a body name the part lacks.
std::optional<TriangleMesh> printed_cad(const TriangleMesh& mesh, const std::vector<SectionParams>& sections);

}  // namespace beadtwin::slicer
