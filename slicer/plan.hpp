// Sectioned path planning (the Thermwood patent's sectioned slicing): the part is divided into
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
#include "slicer/section_params.hpp"

namespace beadtwin::slicer {

// What plan_toolpath found while planning, for the report.
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
