#include "scenarios/params.hpp"

#include <cmath>

#include <fmt/format.h>

namespace beadtwin::scenarios {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using D = Dimension;
using T = ParamType;

// Section parameters. Keys follow the patent's parameter list, paragraphs (41)-(63).
constexpr ParamSpec kSection[] = {
    {"name", T::kString, D::kDimensionless, "", 0, 0, false,
     "name of the section, used in reports and variant paths", "patent (12)"},
    {"body", T::kString, D::kDimensionless, "", 0, 0, false,
     "slice only this body of the part (a mesh file's object); absent: the whole part", "patent (12), (35)",
     true},
    {"tool", T::kString, D::kDimensionless, "", 0, 0, false,
     "name of a tool / melt configuration under `tools:`; it gives bead_width and layer_height unless set "
     "here",
     "patent (48)", true},
    {"outline.points", T::kQuantity, D::kLength, "", 0, 0, false,
     "AM Outline: the 2-D path [[x, y], ...] the section prints itself, layer after layer, instead of "
     "slicing",
     "patent (39) AM Outline", true},
    {"outline.closed", T::kBool, D::kDimensionless, "true", 0, 0, false,
     "the outline path returns to its start", "patent (39)"},
    {"variable_height.slope", T::kQuantity, D::kFraction, "0", -1, 1, false,
     "AM Outline: the bead grows this much taller per length along the direction (2 % is 0.02 mm per mm); "
     "the flow stays constant and the head slows where the bead is taller",
     "seed 002 eqs. 4-12"},
    {"variable_height.direction", T::kQuantity, D::kDimensionless, "[1, 0]", 0, 0, false,
     "AM Outline: the plane direction [x, y] the bead's height grows along", "seed 002 eq. 4"},
    {"layers", T::kInteger, D::kDimensionless, "", 1, 100000, false,
     "number of layers, instead of an upper Z limit (for AM Outline sections)", "patent (39)", true},
    {"z", T::kQuantity, D::kLength, "", -kInf, kInf, false,
     "Z limits [lower, upper] of the section; 'part' for the whole part", "patent (41) Z limits"},
    {"layer_height", T::kQuantity, D::kLength, "0.2 in", 0, 100, true,
     "layer height (bead thickness after the roller)", "patent (45), (48)"},
    {"bead_width", T::kQuantity, D::kLength, "0.83 in", 0, 500, true, "bead width after the roller",
     "patent (48), (54)"},
    {"speed", T::kQuantity, D::kSpeed, "", 0, kInf, true,
     "print speed; when absent, matched to the extruder output: v = Q / A", "docs/physics.md", true},
    {"travel_speed", T::kQuantity, D::kSpeed, "", 0, kInf, true,
     "speed of moves without material; when absent, the machine's max travel speed", "patent (51)", true},
    {"start_point", T::kQuantity, D::kLength, "[0, 0]", -kInf, kInf, false,
     "closed passes start at the contour point nearest this [x, y]", "patent (43) start point location"},
    {"seam_offset", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "distance the start of each closed pass moves along the contour from one layer to the next",
     "patent (43) seam avoidance offset"},
    {"chord_tolerance", T::kQuantity, D::kLength, "0", 0, 100, false,
     "outlines may depart this far from the part to smooth the toolpath (0: follow it exactly)",
     "patent (41) tessellation chord tolerance"},
    {"min_polygon_area", T::kQuantity, D::kArea, "0", 0, kInf, false,
     "outline contours smaller than this are left out", "patent (47) remove small polygons"},
    {"shift", T::kQuantity, D::kLength, "[0, 0]", -kInf, kInf, false,
     "moves the section's toolpath by [dx, dy] so its beads overlap a neighbouring section's where they must "
     "fuse",
     "patent (15), (67)"},
    {"contact_offset", T::kQuantity, D::kLength, "0", -kInf, kInf, false,
     "the section prints this far above (below, if negative) its Z limits, e.g. -2 in to print a section "
     "whose limits start at 2 in on the table",
     "patent (44)-(45) contact tip-workpiece"},
    {"outer_stock", T::kQuantity, D::kLength, "0", -kInf, kInf, false,
     "stock to leave outside the outer contours: the outline grows by this before the passes are placed",
     "patent (45) outer stock to leave"},
    {"inner_stock", T::kQuantity, D::kLength, "0", -kInf, kInf, false,
     "stock to leave inside the holes: they shrink by this", "patent (45) inner stock to leave"},
    {"combine_stock_offset", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "stock and toolpath offsets as one sharp-cornered offset; false: the stock envelope at constant "
     "distance "
     "(round at convex corners) first, the passes offset from it",
     "patent (45) combine stock offset with toolpath offset"},
    {"containment.outside", T::kQuantity, D::kLength, "", 0, 0, false,
     "outside containment boundary [[x, y], ...]: the section prints only inside it", "patent (41)", true},
    {"containment.inside", T::kQuantity, D::kLength, "", 0, 0, false,
     "inside containment boundaries [[x, y], ...] (or a list of them): the section prints only outside them",
     "patent (41)", true},
    {"slice_plane", T::kString, D::kDimensionless, "top", 0, 0, false,
     "plane the layers lie in: top (the part as modelled), front (its XZ plane; +Y up) or side (its YZ "
     "plane; +X up)",
     "patent (44) slice plane"},
    {"shares_wall_with", T::kString, D::kDimensionless, "", 0, 0, false,
     "name of a section whose wall this one uses where they meet: no wall of its own there, its passes and "
     "fill run up to the other's",
     "patent (17)", true},
    {"merge_slices", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "use the largest outline of the previous, this and the next layer (extra stock on sloped walls)",
     "patent (44) merge slices for extra stock"},
    {"ignore_inner_contours", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "leave holes out of the slice: every outline prints solid", "patent (44)"},
    {"layer_order", T::kString, D::kDimensionless, "boundary_first", 0, 0, false,
     "boundary_first or fill_first", "patent (44) layer order"},
    {"arc_chord_tolerance", T::kQuantity, D::kLength, "0", 0, 100, false,
     "runs of print moves within this of a circular arc are written as one G2/G3 arc, where the machine's "
     "dialect allows arcs (0: straight moves only)",
     "patent (45) arc chord tolerance"},
    {"clearance_height", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "height above the table the head rises to between layers (0: moves on at the layer's height)",
     "patent (45) clearance height"},
    {"melt_reduction", T::kQuantity, D::kFraction, "0", 0, 1, false,
     "the pump slows by this much where a bead is laid over one just laid (start/stop overlap, lead-out "
     "along "
     "the pass)",
     "patent (46) melt settings"},
    {"initial_clearance_height", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "height above the table the head starts the program at (0: at the first layer's height)",
     "patent (45) initial clearance height"},
    {"rafts", T::kInteger, D::kDimensionless, "0", 0, 100, false,
     "solid layers printed under the lowest section's first layer; the part sits on them",
     "patent (46) rafts"},
    {"stock_on_top", T::kInteger, D::kDimensionless, "0", 0, 100, false,
     "solid layers printed on the section's top layer, with its outline", "patent (46) stock on top"},
    {"pull_back.length", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "the roller lifts this far before a corner (0 with no extension: no pull-back)",
     "patent (47) pull-back length"},
    {"pull_back.extension", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "and re-engages this far after it, away from the corner", "patent (47) pull-back extension"},
    {"pull_back.min_turn", T::kQuantity, D::kAngle, "60 deg", 0, 180, false,
     "a corner is a turn of the path at least this sharp", "patent (47)"},
    {"smoothing.smooth_curves", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "chord-tolerance simplification keeps curves smooth: no facet turns more than 10 deg where the part "
     "runs smoothly",
     "patent (47) maintain smooth curves"},
    {"smoothing.never_start_in_corner", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "closed passes start at least a bead width from any corner (a turn of 30 deg or more)",
     "patent (47) never start in a corner"},
    {"smoothing.min_polygon_angle", T::kQuantity, D::kAngle, "0 deg", 0, 180, false,
     "pass corners with an interior angle below this are cut back half a bead width along both edges",
     "patent (47) minimum polygon angle"},
    {"voids.detect", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "after each layer is planned, find the parts of its outline no bead covers; counted in the report",
     "patent (46) void detection"},
    {"voids.fill", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "and lay a bead of its own width down the centre of each void found", "patent (46) void detection"},
    {"voids.min_width", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "voids narrower than this are left to the roller's squeeze (0: a quarter of the bead width)",
     "patent (46)"},
    {"melt_on.prime", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "prime the melt when a bead starts: the pump runs at the priming speed for the prime time",
     "patent (51) prime melt when turning on"},
    {"melt_on.delay_during_prime", T::kBool, D::kDimensionless, "true", 0, 0, false,
     "the head waits while priming; false: it moves off and the prime adds to the first stretch of bead",
     "patent (51) delay during priming"},
    {"melt_on.prime_time", T::kQuantity, D::kTime, "0", 0, 600, false, "how long the prime runs",
     "patent (51) prime time"},
    {"melt_on.prime_rpm", T::kQuantity, D::kRotationalSpeed, "0", 0, kInf, false,
     "pump or screw speed while priming", "patent (51) priming RPM"},
    {"melt_off.coast", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "the pump stops the coast distance before a bead's end and the head coasts on; the nozzle's pressure "
     "lays a bead thinning to nothing",
     "patent (52) apply coast off motion"},
    {"melt_off.coast_distance", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "distance before the bead's end where the pump stops", "patent (52) coast distance"},
    {"melt_off.reverse", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "reverse the pump when a bead ends, drawing material back from the nozzle",
     "patent (52) reverse melt when turning off"},
    {"melt_off.reverse_during_coast", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "the reverse starts with the coast instead of at the bead's end", "patent (53)"},
    {"melt_off.delay_during_reverse", T::kBool, D::kDimensionless, "true", 0, 0, false,
     "the head waits for the reverse time", "patent (53) delay during reverse"},
    {"melt_off.reverse_time", T::kQuantity, D::kTime, "0", 0, 600, false, "how long the pump reverses",
     "patent (53) reverse time"},
    {"melt_off.reverse_rpm", T::kQuantity, D::kRotationalSpeed, "0", 0, kInf, false,
     "pump or screw speed while reversing", "patent (53) reverse RPM"},
    {"melt_set_at_control", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "prime and reverse times and speeds are the controller's: the program only starts them",
     "patent (53) set at control"},
    {"boundary.passes", T::kInteger, D::kDimensionless, "1", 0, 50, false,
     "number of boundary beads along each contour", "patent (49)-(50), FIG. 6"},
    {"boundary.overlap", T::kQuantity, D::kFraction, "10 %", 0, 0.5, false,
     "least overlap between neighbouring boundary passes, fraction of the bead width",
     "patent (50) pass overlap"},
    {"boundary.max_overlap", T::kQuantity, D::kFraction, "100 %", 0, 1, false,
     "most that two sides of one pass may overlap where the outline narrows; the pass is left out where they "
     "would overlap more (100 %: no limit)",
     "patent (50) maximum pass overlap"},
    {"boundary.inside_out", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "lay the innermost boundary pass first", "patent (49)"},
    {"boundary.reverse_alternate", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "run every other layer's boundary passes the opposite way round", "patent (49)"},
    {"boundary.lead_in", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "bead laid on a straight approach before each boundary pass", "patent (50) lead-in length"},
    {"boundary.lead_out", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "bead laid on a straight run-off after each boundary pass, tangent to its end",
     "patent (50) lead-out length"},
    {"boundary.force_tangential_lead_out", T::kBool, D::kDimensionless, "true", 0, 0, false,
     "lead-out straight on, tangent to the pass's end; false: on along the pass itself", "patent (50)"},
    {"boundary.start_stop_overlap", T::kQuantity, D::kFraction, "0", 0, 1, false,
     "a closed pass runs on past its start by this fraction of the bead width",
     "patent (50) start/stop overlap"},
    {"boundary.min_pass_length", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "closed passes shorter than this are left out", "patent (49) minimum pass length"},
    {"boundary.thin_walls", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "search for walls too narrow for a bead's centre to reach and lay one bead of their width down their "
     "centre",
     "patent (50) thin wall sections"},
    {"boundary.thin_wall_max_width", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "walls wider than this are not filled as thin walls (0: the bead width)", "patent (50) maximum width"},
    {"boundary.thin_wall_one_bead_width", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "thin walls up to this wide get one bead; wider ones two side by side (0: the bead width)",
     "patent (50) maximum width for one bead"},
    {"boundary.thin_wall_thickness_deviation", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "a thin-wall bead keeps one width while the wall stays within this of it; beyond, a new width starts "
     "(0: the width follows the wall)",
     "patent (50) maximum thickness deviation"},
    {"boundary.thin_wall_stitching_gap", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "thin-wall centre lines whose ends are closer than this are stitched into one bead",
     "patent (50) maximum stitching gap"},
    {"boundary.thin_wall_intersection_distance", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "thin-wall centre lines ending this close to another line or a pass are extended to meet it",
     "patent (50) maximum intersection distance"},
    {"fill.angle", T::kQuantity, D::kAngle, "45 deg", -360, 360, false,
     "fill direction of the section's first layer", "patent (63) starting fill angle"},
    {"fill.angle_step", T::kQuantity, D::kAngle, "90 deg", -360, 360, false,
     "change in fill angle from one layer to the next", "patent (63) change in angle per layer"},
    {"fill.overlap", T::kQuantity, D::kFraction, "10 %", 0, 0.5, false,
     "least overlap between neighbouring fill passes, fraction of the bead width",
     "patent (63) pass overlap"},
    {"fill.style", T::kString, D::kDimensionless, "smart_zigzag", 0, 0, false,
     "one_way, simple_zigzag, smart_zigzag, smart_zigzag_constant_overlap, sparse_zigzag or "
     "variable_bead_regions",
     "patent (56)-(62), FIGS. 15-19"},
    {"fill.max_overlap", T::kQuantity, D::kFraction, "50 %", 0, 0.9, false,
     "most overlap between fill passes; the constant-overlap style spaces its passes evenly up to it",
     "patent (63) maximum pass overlap"},
    {"fill.max_sparse_spacing", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "sparse zigzag: centre-to-centre spacing of the first serpentine (0: twice the pass pitch)",
     "patent (63) maximum sparse fill spacing"},
    {"fill.sparse_fill_gaps", T::kBool, D::kDimensionless, "true", 0, 0, false,
     "sparse zigzag: after the sparse serpentine, lay the passes that fill its gaps (false: the fill stays "
     "sparse, with solid top and bottom surfaces)",
     "patent (61), FIG. 19"},
    {"fill.boundary_overlap", T::kQuantity, D::kFraction, "", 0, 0.9, false,
     "fill pass ends reach into the boundary beads by this fraction of the bead width; absent: the pass "
     "overlap",
     "patent (63) boundary overlap", true},
    {"fill.boundary_side_overlap", T::kQuantity, D::kFraction, "", 0, 0.9, false,
     "fill passes beside the boundary overlap it by this fraction of the bead width; absent: the pass "
     "overlap",
     "patent (63) boundary side overlap", true},
    {"fill.max_end_overlap", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "most a fill pass's end may cross into a boundary bead (0: no limit)",
     "patent (64) max end overlap distance"},
    {"fill.max_side_overlap", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "most a fill pass's side may cross into a boundary bead (0: no limit)",
     "patent (64) max side overlap distance"},
    {"fill.optimize_to_surface", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "accuracy first: pass ends reach into the boundary as far as the end-overlap limit allows (a bead width "
     "if none), instead of the boundary overlap",
     "patent (63) optimize to surface features"},
    {"fill.link_with_rapids", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "every fill pass is its own bead: the melt stops and the head rapids to the next pass",
     "patent (63) linking passes with rapids"},
    {"fill.min_length", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "fill passes shorter than this are left out", "patent (63) minimum fill length"},
    {"fill.lead_in", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "bead laid on a straight approach before each fill bead", "patent (63) lead-in length"},
    {"fill.lead_out", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "bead laid on a straight run-off after each fill bead", "patent (63) lead-out length"},
    {"fill.force_tangential_lead_out", T::kBool, D::kDimensionless, "true", 0, 0, false,
     "fill lead-out straight on, tangent to the bead's end; false: back along the last pass",
     "patent (63) force tangential lead-out"},
    {"fill.fillet_radius", T::kQuantity, D::kFraction, "0", 0, 1, false,
     "corners of the fill's turns rounded with this fraction of the bead's radius (w/2)",
     "patent (64) fillet radius on path corners"},
    {"fill.corner_melt_reduction", T::kQuantity, D::kFraction, "0", 0, 0.9, false,
     "the pump slows by this fraction on the fill's turns", "patent (64) melt output reduction in corners"},
    {"fill.corner_speed", T::kQuantity, D::kSpeed, "", 0, kInf, true,
     "head speed on the fill's turns; absent: the same as the fill passes",
     "patent (64) travel speed on corners", true},
    {"fill.turns_outside", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "place the fill's turns outside the fill region (into the boundary beads)",
     "patent (64) place fill turns outside section boundary"},
    {"fill.line_matching_limit", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "at a turn between passes of different length the shorter is extended to be even with the longer, up to "
     "this (0: never)",
     "patent (64) limit to fill line matching"},
    {"fill.line_extension", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "fill passes run on this far beyond the fill region before they turn",
     "patent (65) fill line extension"},
    {"fill.step_tolerance", T::kQuantity, D::kLength, "0", 0, kInf, false,
     "sparse fill without gap passes: top and bottom surfaces narrower than this are not made solid (0: the "
     "bead width)",
     "patent (65) step tolerance"},
    {"fill.angle_tolerance", T::kQuantity, D::kAngle, "5 deg", 0, 45, false,
     "sparse fill without gap passes: part faces within this of horizontal are top or bottom surfaces, whose "
     "layers are filled solid",
     "patent (65) angle tolerance"},
};

constexpr ParamSpec kMachine[] = {
    {"name", T::kString, D::kDimensionless, "", 0, 0, false, "machine name", ""},
    {"description", T::kString, D::kDimensionless, "-", 0, 0, false, "what the machine is", ""},
    {"kind", T::kString, D::kDimensionless, "roller-gantry", 0, 0, false,
     "roller-gantry, tamper-gantry, robot or desktop", "patent (33)"},
    {"max_feed", T::kQuantity, D::kSpeed, "20 in/s", 0, kInf, true, "highest print speed the gantry runs",
     "estimate"},
    {"max_travel", T::kQuantity, D::kSpeed, "40 in/s", 0, kInf, true,
     "highest speed of moves without material", "estimate"},
    {"acceleration", T::kQuantity, D::kAcceleration, "40 in/s2", 0, kInf, true,
     "gantry acceleration for the motion model", "estimate"},
    {"junction_deviation", T::kQuantity, D::kLength, "0.02 in", 0, kInf, true,
     "corner deviation the controller allows; sets cornering speed", "estimate"},
    {"roller.width", T::kQuantity, D::kLength, "0", 0, 1000, false,
     "width of the compression roller (or tamper) across the bead; corners tighter than half of it are "
     "reported where the roller stays down (0: unknown, no check)",
     "estimate per machine"},
    {"roller.diameter", T::kQuantity, D::kLength, "0", 0, 1000, false,
     "diameter of the compression roller: material standing up to its radius above a bead's top is in its "
     "way (0: unknown, a layer height is looked at)",
     "estimate per machine"},
    {"nozzle_diameter", T::kQuantity, D::kLength, "0", 0, 100, false,
     "diameter of the nozzle's tip; travel moves are checked for collisions over it (0: its centre only)",
     "machine data"},
    {"extruder.output", T::kQuantity, D::kMassFlow, "150 lb/h", 0, kInf, true,
     "nominal extruder output, which sets the print speed where a section gives none",
     "Thermwood PH15 print head"},
    {"extruder.max_output", T::kQuantity, D::kMassFlow, "200 lb/h", 0, kInf, true,
     "most the extruder can deliver", "estimate"},
    {"extruder.kind", T::kString, D::kDimensionless, "gear_pump", 0, 0, false,
     "gear_pump, screw or filament: what turns flow into extruder commands", "patent (51), seed 002 eq. 1"},
    {"extruder.displacement", T::kQuantity, D::kVolume, "0", 0, kInf, false,
     "material per revolution of the pump or screw (cm3/rev); 0: the program carries no speed words",
     "estimate per machine"},
    {"extruder.filament_diameter", T::kQuantity, D::kLength, "0", 0, 100, false,
     "filament diameter d_f of a filament extruder (E words)", "seed 002 eq. 1"},
    {"extruder.constant_feed", T::kQuantity, D::kSpeed, "0", 0, 1000, false,
     "filament extruder whose drive the program only switches on and off: it feeds the filament at this "
     "constant v_e from melt_on to melt_off, Q = π d_f² v_e / 4, and where a program's moves carry no E "
     "word the head's feed sets the bead, A = Q / v (0: the flow comes from E or speed words)",
     "seed 002 eqs. 1 and 12, Table 1"},
    {"extruder.ooze_time", T::kQuantity, D::kTime, "0", 0, 1000, false,
     "time constant of the nozzle's pressure after a melt off: without a coast or a reverse the melt oozes "
     "on, its flow falling as exp(-t/τ), onto the dwells and travels that follow (0: no ooze)",
     "estimate per machine and material"},
    {"extruder.max_rpm", T::kQuantity, D::kRotationalSpeed, "0", 0, kInf, false,
     "highest pump or screw speed; a program that needs more is reported (0: no limit)", "machine data"},
    {"environment.ambient", T::kQuantity, D::kTemperature, "18 C", -50, 100, false, "ambient air temperature",
     "Compton et al. 2017"},
    {"environment.bed_temp", T::kQuantity, D::kTemperature, "65 C", -50, 300, false, "table temperature",
     "Compton et al. 2017"},
    {"environment.bed_insulated", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "table is an insulator (no heat flows into it)", ""},
    {"environment.convection", T::kQuantity, D::kHeatTransferCoeff, "7 W/m2K", 0, 1000, false,
     "natural convection coefficient on free faces", "Compton et al. 2017"},
    {"environment.convection_by_height", T::kQuantity, D::kHeatTransferCoeff, "", 0, 1000, false,
     "convection coefficient by height above the table instead: [[height, h], ...] in increasing height, "
     "linear between the points, constant beyond them (h in W/m2K unless given with units)",
     "thermal/heat.hpp", true},
    {"environment.bed_contact", T::kQuantity, D::kHeatTransferCoeff, "100 W/m2K", 0, 1e5, false,
     "contact conductance between the first layer and the table", "estimate"},
    {"gcode.units", T::kString, D::kDimensionless, "in", 0, 0, false, "units of the print program: in or mm",
     ""},
    {"gcode.arcs", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "the controller takes G2/G3 arcs (XY plane, I/J centre offsets from the start)", "patent (45)"},
    {"gcode.roller_down", T::kString, D::kDimensionless, "none", 0, 0, false,
     "code that lowers the compression roller onto the bead (none: the program does not switch it)",
     "patent (47) corner pull-back"},
    {"gcode.roller_up", T::kString, D::kDimensionless, "none", 0, 0, false,
     "code that lifts the compression roller off the bead", "patent (47) corner pull-back"},
    {"gcode.macro_step_limit", T::kInteger, D::kDimensionless, "10000000", 1000, 2000000000, false,
     "statements a macro program may run before it is stopped as an endless loop", ""},
    {"gcode.macro_loops", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "Fanuc macro program: layers that repeat one path are written once in a WHILE loop stepping Z",
     "seed 002 section 2.7"},
    {"gcode.rapid_g0", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "G0 runs at the machine's max travel speed whatever its F, as CNC controllers run it (false: at the "
     "programmed feed, as Marlin and RepRap firmware do); travel slower than that is written as G1",
     "ISO 6983-1 G00 positioning at rapid traverse"},
    {"gcode.absolute_e", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "filament machines: E as a running total (M82) instead of per move (M83)", "Marlin/RepRap dialect"},
    {"gcode.heat_on", T::kString, D::kDimensionless, "none", 0, 0, false,
     "code that turns the extruder's heaters on, written at the program's start (none: not written)",
     "seed 002 (M27)"},
    {"gcode.heat_off", T::kString, D::kDimensionless, "none", 0, 0, false,
     "code that turns them off, at the program's end", "seed 002 (M28)"},
    {"gcode.rpm_word", T::kString, D::kDimensionless, "S", 0, 0, false,
     "address of the pump or screw speed in the program (with a displacement)", "patent (51)"},
    {"gcode.prime_code", T::kString, D::kDimensionless, "none", 0, 0, false,
     "code that starts a prime (none: a comment)", "patent (51)"},
    {"gcode.reverse_on", T::kString, D::kDimensionless, "none", 0, 0, false,
     "code that reverses the pump (none: a comment)", "patent (52)"},
    {"gcode.reverse_off", T::kString, D::kDimensionless, "none", 0, 0, false,
     "code that ends the reverse (none: a comment)", "patent (52)"},
    {"gcode.melt_on", T::kString, D::kDimensionless, "M23", 0, 0, false,
     "code that starts the extruder (none: machines that extrude by E)", "seed 002, Fanuc macro programs"},
    {"gcode.melt_off", T::kString, D::kDimensionless, "M24", 0, 0, false, "code that stops the extruder",
     "seed 002, Fanuc macro programs"},
};

constexpr ParamSpec kMaterial[] = {
    {"name", T::kString, D::kDimensionless, "", 0, 0, false, "material name", ""},
    {"description", T::kString, D::kDimensionless, "-", 0, 0, false, "what the material is", ""},
    {"density", T::kQuantity, D::kDensity, "", 0, 1e5, true, "density of the printed material", ""},
    {"specific_heat", T::kQuantity, D::kSpecificHeat, "", 0, 1e5, true, "specific heat capacity", ""},
    {"specific_heat_by_temp", T::kQuantity, D::kSpecificHeat, "", 0, 1e5, true,
     "specific heat by temperature instead: [[T, c_p], ...] in increasing temperature, linear between the "
     "points, constant beyond them",
     "thermal/heat.hpp", true},
    {"conductivity.along", T::kQuantity, D::kConductivity, "", 0, 1e3, true,
     "thermal conductivity along the bead", ""},
    {"conductivity.across", T::kQuantity, D::kConductivity, "", 0, 1e3, true,
     "thermal conductivity across the bead, in the layer plane", ""},
    {"conductivity.through", T::kQuantity, D::kConductivity, "", 0, 1e3, true,
     "thermal conductivity through the layer thickness", ""},
    {"emissivity", T::kQuantity, D::kFraction, "", 0, 1, false, "surface emissivity for radiation", ""},
    {"deposition_temp", T::kQuantity, D::kTemperature, "", 0, 600, true,
     "temperature of the bead leaving the nozzle", ""},
    {"glass_transition", T::kQuantity, D::kTemperature, "", -100, 500, false,
     "glass transition temperature T_g", ""},
    {"fusion.support_limit", T::kQuantity, D::kTemperature, "", -100, 600, false,
     "substrate hotter than this when the next layer lands: too hot (slump)", "docs/physics.md"},
    {"fusion.healing_ref_temp", T::kQuantity, D::kTemperature, "", -100, 600, false,
     "reference temperature T_ref of the reptation time", "Yang & Pitchumani 2002"},
    {"fusion.reptation_time", T::kQuantity, D::kTime, "", 0, 1e9, true,
     "reptation (welding) time t_w at T_ref", "Yang & Pitchumani 2002"},
    {"fusion.activation_energy", T::kQuantity, D::kMolarEnergy, "", 0, 1e7, true,
     "activation energy E_a of the reptation time's Arrhenius shift", "Yang & Pitchumani 2002"},
    {"fusion.min_healing_temp", T::kQuantity, D::kTemperature, "", -100, 600, false,
     "below this an interface does not heal", ""},
    {"fusion.required_healing", T::kQuantity, D::kFraction, "", 0, 1, true,
     "degree of healing D_h an interface needs; less is too cold", ""},
    {"price", T::kQuantity, D::kDimensionless, "0", 0, kInf, false, "price per kg, in the user's currency",
     ""},
};

constexpr ParamSpec kOutput[] = {
    {"voxel_size", T::kQuantity, D::kLength, "0", 0, 1000, false,
     "voxel edge of the deposit model; 0 picks half the smallest layer height", "docs/physics.md"},
    {"memory_budget", T::kQuantity, D::kDimensionless, "0", 0, 1e6, false,
     "memory the run may use, GB: a run whose deposit, with what the later stages build from it (checked "
     "again once the deposit's surface is known), would need more stops with a voxel size that fits, or "
     "an automatic voxel size is made coarser; a part mesh with advice to decimate it (0: three quarters "
     "of the machine's memory)",
     "docs/RELIABILITY.md"},
    {"skin", T::kString, D::kDimensionless, "ply", 0, 0, false,
     "the as-printed outer skin as a triangle mesh in mm (the deposit's surface fill = 0.5): ply, stl "
     "or none",
     "sim/skin.hpp"},
    {"skin_adaptivity", T::kQuantity, D::kDimensionless, "0", 0, 1, false,
     "how much the skin mesh merges triangles where the surface is flat before it is simplified: 0 about two "
     "per voxel face crossed, the surface the pictures draw, meshed once for both; 0.2 keeps the ridges "
     "between beads within about a voxel and ends a few per cent smaller once simplified, for a second "
     "meshing; near 1 it may cut through thin walls",
     "OpenVDB tools::volumeToMesh"},
    {"skin_tolerance", T::kQuantity, D::kLength, "0.3 mm", 0, 100, false,
     "the skin mesh is then simplified (edge collapse) as long as its surface moves less than this; 0 keeps "
     "the mesher's triangles",
     "meshoptimizer meshopt_simplify"},
    {"fields", T::kString, D::kDimensionless, "none", 0, 0, false,
     "the voxel fields fill, time_s and layer for ParaView: vtu (VTK XML unstructured grid, one cell "
     "per voxel holding material; about 60 bytes a voxel, 200 MB for the default scenario) or none",
     "sim/deposit_files.hpp"},
    {"history_layers", T::kInteger, D::kDimensionless, "[0, 14, 29]", 0, 100000, false,
     "a list of toolpath layers (numbered from 0 at the table, as in the report's layer table) whose mean "
     "temperature against time report.html plots and report.json keeps (temperature_history), every "
     "thermal.sample_interval; layers the print does not reach are left out; [] for none. The default is "
     "the 1st, 15th and 30th layer",
     "scenarios/report_html.cpp"},
};

constexpr ParamSpec kRender[] = {
    {"width", T::kInteger, D::kDimensionless, "1280", 16, 8192, false, "width of the pictures, pixels", ""},
    {"height", T::kInteger, D::kDimensionless, "800", 16, 8192, false, "height of the pictures, pixels", ""},
    {"samples", T::kInteger, D::kDimensionless, "8", 1, 1024, false,
     "rays per pixel (stratified): smoother edges, shadows and occlusion for more time", "render/render.hpp"},
    {"ambient_occlusion", T::kBool, D::kDimensionless, "true", 0, 0, false,
     "darken the grooves between beads and layers by the sky they cannot see, so ridges and layer lines "
     "read",
     "render/render.hpp"},
    {"legend", T::kBool, D::kDimensionless, "true", 0, 0, false,
     "a title, a legend with the colour scale and its unit, and a scale bar on every picture",
     "render/annotate.hpp"},
    {"exr", T::kBool, D::kDimensionless, "false", 0, 0, false,
     "each picture also as OpenEXR: linear RGB and a channel of the coloured quantity's raw value per pixel "
     "(NaN off the part), and depth",
     "render/image.hpp"},
    {"sheet", T::kBool, D::kDimensionless, "true", 0, 0, false,
     "a comparison sheet per picture: the variants side by side, same camera, same colour scale", ""},
    {"images", T::kString, D::kDimensionless, "", 0, 0, false,
     "the pictures of every variant, a list of maps (keys in the next table); without it: fusion from the "
     "isometric and top views, sections, substrate temperature and, with a part mesh, the deviation",
     "", true},
    {"progress", T::kString, D::kDimensionless, "none", 0, 0, false,
     "a picture per layer as the part grows, for a video: a map {colour, view, every} (keys as for an image, "
     "every: 1 takes every layer), or none",
     ""},
};

constexpr ParamSpec kImage[] = {
    {"name", T::kString, D::kDimensionless, "", 0, 0, false,
     "file name without extension, unique among the pictures; default: the colouring and the view", "", true},
    {"colour", T::kString, D::kDimensionless, "", 0, 0, false,
     "what colours the part: fusion (verdict), section, layer, time (of deposition), substrate "
     "(temperature of what a bead landed on), healing (least degree of healing), deviation (stock over "
     "the CAD), porosity (local void fraction) or temperature (at `time`)",
     "docs/physics.md"},
    {"view", T::kString, D::kDimensionless, "isometric", 0, 0, false,
     "isometric, top, front (from -y), side (from +x), or user (the camera keys)", ""},
    {"camera.position", T::kQuantity, D::kLength, "", 0, 0, false,
     "user view: the eye [x, y, z]; without it the camera looks along camera.direction, framed on the part",
     "", true},
    {"camera.target", T::kQuantity, D::kLength, "", 0, 0, false,
     "user view: the point looked at [x, y, z]; default the part's centre", "", true},
    {"camera.direction", T::kQuantity, D::kDimensionless, "[-1, 1, -1]", 0, 0, false,
     "user view without a position: the viewing direction [x, y, z]", ""},
    {"field_of_view", T::kQuantity, D::kAngle, "30 deg", 0, 120, false,
     "perspective angle of the isometric and user views across the picture's shorter side; 0 draws them "
     "orthographic. Top, front and side are always orthographic",
     ""},
    {"cut.point", T::kQuantity, D::kLength, "", 0, 0, false,
     "a cutaway: a point of the cutting plane [x, y, z]; the inside shows where the plane cuts the part", "",
     true},
    {"cut.normal", T::kQuantity, D::kDimensionless, "[0, -1, 0]", 0, 0, false,
     "the cutting plane's normal [x, y, z]: the half it points into is taken away", ""},
    {"layer", T::kInteger, D::kDimensionless, "", 0, 1e7, false,
     "the part as it stood when this toolpath layer (from 0) was done; default the finished part", "", true},
    {"time", T::kQuantity, D::kTime, "", 0, 1e9, false,
     "colour temperature: the moment, from the start of the print; default its end", "", true},
    {"range", T::kQuantity, D::kDimensionless, "", 0, 0, false,
     "the colour scale's ends [low, high], in the colouring's unit (°C, s, mm, fraction, layer); default "
     "the data's range",
     "", true},
};

constexpr ParamSpec kThermal[] = {
    {"cells_across", T::kInteger, D::kDimensionless, "3", 1, 15, false,
     "thermal cells across a bead, odd: a centre and two edges at 3", "thermal/mesh.hpp"},
    {"cells_through", T::kInteger, D::kDimensionless, "1", 1, 15, false,
     "thermal cells through a bead's height", "thermal/mesh.hpp"},
    {"cell_length", T::kQuantity, D::kLength, "", 0, 1e5, true,
     "thermal cell length along a bead; absent: two bead widths, made longer (with a note) where that would "
     "be more than 250,000 cells",
     "thermal/mesh.hpp", true},
    {"birth_interval", T::kQuantity, D::kTime, "", 0, 1e4, true,
     "cells laid within this time are born together; absent: a fifth of the cells' median conduction time "
     "constant, made longer (with a note) where the print would need more than 5,000 birth events",
     "thermal/heat.hpp", true},
    {"cooldown", T::kQuantity, D::kTime, "10 min", 0, 1e7, false,
     "time simulated after the last layer (interfaces keep healing)", ""},
    {"sample_interval", T::kQuantity, D::kTime, "5 s", 0, 1e5, true,
     "how often the layers' temperatures are kept for the history plots", ""},
    {"snapshots", T::kQuantity, D::kTime, "", 0, 1e7, false,
     "times [t, ...] (or `end`, the end of the print) at which every cell's temperature is written: "
     "temperature-<t>s.vdb (voxels) and .vtp (cell centroids, ParaView); absent: none",
     "thermal/snapshot_files.hpp", true},
    {"rel_tol", T::kQuantity, D::kDimensionless, "1e-3", 0, 0.1, true, "CVODE relative tolerance", ""},
    {"abs_tol", T::kQuantity, D::kDimensionless, "0.05", 0, 10, true, "CVODE absolute tolerance, kelvin", ""},
    {"lump", T::kBool, D::kDimensionless, "true", 0, 0, false,
     "lump settled cells (more than 20 contacts below the top, within 0.5 K along the bead) into one cell "
     "per "
     "run, with a note: a long print's old layers then cost little in each step; false: keep every cell",
     "docs/physics.md"},
};

// Tool / melt configurations (patent (48)): named bead sets the sections refer to with `tool:`.
constexpr ParamSpec kTool[] = {
    {"description", T::kString, D::kDimensionless, "-", 0, 0, false, "what the configuration is", ""},
    {"material", T::kString, D::kDimensionless, "", 0, 0, false,
     "material it prints; must be the scenario's material when given", "patent (48)", true},
    {"bead_width", T::kQuantity, D::kLength, "", 0, 500, true, "bead width after the roller", "patent (48)"},
    {"bead_thickness", T::kQuantity, D::kLength, "", 0, 100, true,
     "bead thickness after the roller: the layer height of sections using it", "patent (48), (55)"},
};

}  // namespace

std::span<const ParamSpec> tool_params() {
  return kTool;
}
std::span<const ParamSpec> section_params() {
  return kSection;
}
std::span<const ParamSpec> machine_params() {
  return kMachine;
}
std::span<const ParamSpec> material_params() {
  return kMaterial;
}
std::span<const ParamSpec> output_params() {
  return kOutput;
}
std::span<const ParamSpec> thermal_params() {
  return kThermal;
}
std::span<const ParamSpec> render_params() {
  return kRender;
}
std::span<const ParamSpec> image_params() {
  return kImage;
}

}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {
namespace {

std::string type_name(const ParamSpec& p) {
  switch (p.type) {
    case ParamType::kQuantity:
      return std::string(dimension_name(p.dim));
    case ParamType::kInteger:
      return "integer";
    case ParamType::kBool:
      return "true/false";
    case ParamType::kString:
      return "text";
  }
  return "?";
}

std::string range_text(const ParamSpec& p) {
  if (p.type == ParamType::kString || p.type == ParamType::kBool) return "";
  const std::string unit(p.type == ParamType::kQuantity ? internal_unit(p.dim) : "");
  const auto num = [](double v) { return fmt::format("{:g}", v); };
  std::string lo = std::isinf(p.min) ? "" : (p.min_exclusive ? "> " : ">= ") + num(p.min);
  std::string hi = std::isinf(p.max) ? "" : "<= " + num(p.max);
  std::string r = lo.empty() ? hi : hi.empty() ? lo : lo + ", " + hi;
  if (!r.empty() && !unit.empty()) r += " " + unit;
  return r;
}

void table(std::string& out, std::string_view title, std::string_view intro,
           std::span<const ParamSpec> specs) {
  out += fmt::format("\n## {}\n\n{}\n\n", title, intro);
  out += "| key | type | default | range | meaning | source |\n|---|---|---|---|---|---|\n";
  for (const auto& p : specs) {
    const std::string def = !p.default_text.empty() ? fmt::format("`{}`", p.default_text)
                            : p.derived             ? "derived"
                                                    : "required";
    out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", p.key, type_name(p), def, range_text(p),
                       p.meaning, p.source.empty() ? "" : std::string(p.source));
  }
}

}  // namespace

std::string params_markdown() {
  std::string out =
      "# Scenario parameters\n\n"
      "Generated by `beadtwin params` from the one table the scenario loader reads, so it cannot\n"
      "drift from what beadtwin accepts. Quantities take a unit (`0.83 in`, `5 mm`, `240 C`, `150 lb/h`,\n"
      "`45 deg`, `10 %`); a bare number takes the file's `units:` default, else the internal unit the range "
      "is\n"
      "given in. A dotted key is a nested map: `boundary.passes: 2` is written `boundary: {passes: 2}`.\n";
  table(out, "Sections", "Each entry of `sections:`; a variant sets them as `sections.<name>.<key>`.",
        section_params());
  table(out, "Machine", "A file in `machines/` (or an inline `machine:` map); variants set `machine.<key>`.",
        machine_params());
  table(out, "Material",
        "A file in `materials/` (or an inline `material:` map); variants set `material.<key>`.",
        material_params());
  table(out, "Tools (melt configurations)",
        "Each entry of the `tools:` map, by name; sections refer to one with `tool: <name>`.", tool_params());
  table(out, "Output", "The `output:` block.", output_params());
  table(out, "Thermal solver", "The `thermal:` block.", thermal_params());
  table(out, "Pictures", "The `render:` block.", render_params());
  table(out, "Pictures: each image",
        "Each entry of `render.images:` (and the `render.progress:` map, which takes `colour`, `view`, the "
        "camera keys and `every`).",
        image_params());
  return out;
}

}  // namespace beadtwin::scenarios
