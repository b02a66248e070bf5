// Sectioned path planning (the Thermwood patent's sectioned slicing, first cut): the part is divided into
// sections by Z range, each with its own layer height, bead, speed, boundary passes and fill; each section
// is sliced into planar layers; each layer gets its boundary passes (offsets of the outline) and, where
// asked, a zigzag fill whose angle turns from layer to layer; the layers of all sections are merged by Z
// into one Toolpath.
#pragma once

#include <string>
#include <vector>

#include "core/toolpath.hpp"
#include "slicer/mesh.hpp"

namespace beadtwin::slicer {

struct BoundaryParams {
  int passes = 1;                  // beads laid along each contour, outermost first (patent (49))
  double overlap = 0.10;           // overlap between neighbouring passes, fraction of the bead width
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
  // Thin walls (patent (50)): parts of the outline too narrow for a bead's centre to reach, no wider than
  // thin_wall_max_width_mm, get one bead of their own width down their centre line.
  bool thin_walls = false;
  double thin_wall_max_width_mm =
      0.0;  // 0: the bead width  // closed passes shorter than this are left out (patent (49))
};

struct FillParams {
  bool enabled = false;
  double angle_deg = 45.0;       // fill direction of the section's first layer (patent (63))
  double angle_step_deg = 90.0;  // change in fill angle from one layer to the next (patent (63))
  double overlap = 0.10;         // overlap between fill passes, and between fill and boundary, fraction of w
};

struct SectionParams {
  std::string name;
  std::string body;  // slice only this body of the part (patent (12), (35)); empty: the whole part
  // AM Outline (patent (39)): when set, the section prints this 2-D path itself, layer after layer, instead
  // of slicing the part.
  std::vector<Eigen::Vector2d> outline_path;
  bool outline_closed = true;
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
  double contact_offset_mm =
      0.0;  // the section prints this much above (below, negative) its Z limits (patent (45))
  // Toolpath parameters (patent (44)-(45)).
  double outer_stock_mm = 0.0;         // the outline's outer contours grow by this (stock to machine off)
  double inner_stock_mm = 0.0;         // the outline's holes shrink by this
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
  BoundaryParams boundary;
  FillParams fill;
};

struct PlanStats {
  int empty_layers = 0;  // layers whose slice was empty (nothing to print there)
  int open_chains = 0;   // slice loops that did not close (mesh holes), summed over layers
};

// Plans every section and merges their layers by height into one Toolpath (times from `motion`). Sections
// may overlap in Z only when they slice different bodies (checked by the scenario loader). Throws InputError
// on parameters the planner cannot use.
Toolpath plan_toolpath(const TriangleMesh& mesh, const std::vector<SectionParams>& sections,
                       const MotionLimits& motion, PlanStats* stats = nullptr);

}  // namespace beadtwin::slicer
