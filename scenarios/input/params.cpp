#include "scenarios/input/params.hpp"

#include <cmath>

#include <fmt/format.h>

#include "slicer/section_params.hpp"

namespace beadtwin::scenarios {
namespace {

using D = Dimension;

constexpr std::string_view kSkinFormats[] = {"ply", "stl", "none"};
// output.fields: none (false) or vtu (true).
constexpr std::string_view kFieldFormats[] = {"none", "vtu"};

// The top level of a scenario file. Its blocks are read by their own tables below.
const Param<Scenario> kScenario[] = {
    {{.key = "name", .meaning = "scenario name, in the reports"}, BT_MEMBER(Scenario, name)},
    {{.key = "description", .default_text = "-", .meaning = "what the scenario is for"},
     BT_MEMBER(Scenario, description)},
    {{.key = "units",
      .meaning =
          "default units for bare numbers, per dimension: {length: in, temperature: C, time: s, mass: kg, "
          "speed: in/s, angle: deg, mass_flow: lb/h, volume_flow: cm3/s}; absent: the internal units",
      .derived = true,
      .form = "map"}},
    {{.key = "machine",
      .meaning =
          "the machine: the name of a file in machines/ (beside the scenario, else shipped) or an inline map "
          "of the Machine keys",
      .form = "name, or a map"}},
    {{.key = "material",
      .meaning =
          "the material: the name of a file in materials/ (beside the scenario, else shipped) or an inline "
          "map of the Material keys",
      .form = "name, or a map"}},
    {{.key = "part",
      .meaning =
          "the part: a map of the Part keys; absent when every section prints an AM Outline or a program "
          "is simulated",
      .derived = true,
      .form = "map"}},
    {{.key = "program",
      .meaning = "a print program (G-code or Fanuc macro) to simulate as written instead of slicing a part",
      .derived = true,
      .form = "file path"}},
    {{.key = "sections",
      .meaning = "the sections, a list of maps of the Section keys (none when a program is simulated)",
      .source = "patent (12)",
      .derived = true,
      .form = "list of maps"}},
    {{.key = "tools",
      .meaning = "named tool / melt configurations, a map of name to Tools keys",
      .source = "patent (48)",
      .derived = true,
      .form = "map of maps"}},
    {{.key = "output", .meaning = "a map of the Output keys", .derived = true, .form = "map"}},
    {{.key = "thermal", .meaning = "a map of the Thermal solver keys", .derived = true, .form = "map"}},
    {{.key = "render", .meaning = "a map of the Pictures keys", .derived = true, .form = "map"}},
    {{.key = "variants",
      .meaning =
          "parameter sets, each {name, set: {key.path: value}} with paths as machine.KEY, material.KEY, "
          "part.KEY, output.KEY, render.KEY, thermal.KEY, tools.NAME.KEY, sections.NAME.KEY or program; "
          "absent: one variant, baseline",
      .derived = true}},
    {{.key = "gates",
      .meaning =
          "pass/fail conditions on the metrics, such as 'porosity < 0.03' or 'print_time_s <= baseline * "
          "1.05'",
      .derived = true,
      .form = "list of text"}},
};

// A part: exactly one of a mesh file, a box or an open-top box. Read by read_part (the keys depend on one
// another).
const Param<PartSpec> kPart[] = {
    {{.key = "mesh",
      .meaning = "the part's mesh file (STL, OBJ, 3MF, AMF or PLY), relative to the scenario",
      .derived = true,
      .form = "file path"}},
    {{.key = "mesh_units",
      .default_text = "mm",
      .meaning = "the length unit of the mesh file's coordinates",
      .form = "length unit"}},
    {{.key = "box.size",
      .dim = D::kLength,
      .meaning = "a box: its size [x, y, z]",
      .derived = true,
      .form = "[x, y, z] length"}},
    {{.key = "box.origin",
      .dim = D::kLength,
      .default_text = "[0, 0, 0]",
      .meaning = "a box: its minimum corner",
      .form = "[x, y, z] length"}},
    {{.key = "open_box.size",
      .dim = D::kLength,
      .meaning = "an open-top box: its outer size [x, y, z]",
      .derived = true,
      .form = "[x, y, z] length"}},
    {{.key = "open_box.origin",
      .dim = D::kLength,
      .default_text = "[0, 0, 0]",
      .meaning = "an open-top box: its minimum corner",
      .form = "[x, y, z] length"}},
    {{.key = "open_box.wall",
      .dim = D::kLength,
      .range = {.min = 0, .max = 1e5, .min_exclusive = true},
      .meaning =
          "an open-top box: its wall thickness, or tiers [[z_top, thickness], ...] from the floor up (walls "
          "thinning inside)",
      .derived = true,
      .form = "length, or [[z_top, thickness], ...]"}},
    {{.key = "open_box.floor",
      .dim = D::kLength,
      .range = {.min = 0, .max = 1e5, .min_exclusive = true},
      .meaning = "an open-top box: its floor thickness",
      .derived = true,
      .form = "length"}},
};

// Tool / melt configurations (patent (48)): named bead sets the sections refer to with `tool:`.
const Param<Tool> kTool[] = {
    {{.key = "description", .default_text = "-", .meaning = "what the configuration is"},
     BT_MEMBER(Tool, description)},
    {{.key = "material",
      .meaning = "material it prints; must be the scenario's material when given",
      .source = "patent (48)",
      .derived = true,
      .form = "name, or a map"}},
    {{.key = "bead_width",
      .dim = D::kLength,
      .range = {.min = 0, .max = 500, .min_exclusive = true},
      .meaning = "bead width after the roller",
      .source = "patent (48)"},
     BT_MEMBER(Tool, bead_width_mm)},
    {{.key = "bead_thickness",
      .dim = D::kLength,
      .range = {.min = 0, .max = 100, .min_exclusive = true},
      .meaning = "bead thickness after the roller: the layer height of sections using it",
      .source = "patent (48), (55)"},
     BT_MEMBER(Tool, bead_thickness_mm)},
};

const Param<OutputSpec> kOutput[] = {
    {{.key = "voxel_size",
      .dim = D::kLength,
      .default_text = "0",
      .range = {0, 1000},
      .meaning = "voxel edge of the deposit model; 0 picks half the smallest layer height",
      .source = "docs/physics.md"},
     BT_MEMBER(OutputSpec, voxel_size_mm)},
    {{.key = "memory_budget",
      .default_text = "0",
      .range = {0, 1e6},
      .meaning = "memory the run may use, GB: a run whose deposit, with what the later stages build from "
                 "it (checked again once the deposit's surface is known), would need more stops with a "
                 "voxel size that fits, or an automatic voxel size is made coarser; a part mesh with "
                 "advice to decimate it (0: three quarters of the machine's memory)",
      .source = "docs/RELIABILITY.md"},
     BT_MEMBER(OutputSpec, memory_budget_gb)},
    {{.key = "skin",
      .default_text = "ply",
      .meaning = "the as-printed outer skin as a triangle mesh in mm (the deposit's surface fill = 0.5): "
                 "ply, stl or none",
      .source = "sim/skin.hpp",
      .choices = kSkinFormats,
      .none_is_empty = true},
     BT_MEMBER(OutputSpec, skin_format)},
    {{.key = "skin_adaptivity",
      .default_text = "0",
      .range = {0, 1},
      .meaning = "how much the skin mesh merges triangles where the surface is flat before it is "
                 "simplified: 0 about two per voxel face crossed, the surface the pictures draw, meshed "
                 "once for both; 0.2 keeps the ridges between beads within about a voxel and ends a few "
                 "per cent smaller once simplified, for a second meshing; near 1 it may cut through thin "
                 "walls",
      .source = "OpenVDB tools::volumeToMesh"},
     BT_MEMBER(OutputSpec, skin_adaptivity)},
    {{.key = "skin_tolerance",
      .dim = D::kLength,
      .default_text = "0.3 mm",
      .range = {0, 100},
      .meaning = "the skin mesh is then simplified (edge collapse) as long as its surface moves less than "
                 "this; 0 keeps the mesher's triangles",
      .source = "meshoptimizer meshopt_simplify"},
     BT_MEMBER(OutputSpec, skin_tolerance_mm)},
    {{.key = "fields",
      .default_text = "none",
      .meaning = "the voxel fields fill, time_s and layer for ParaView: vtu (VTK XML unstructured grid, "
                 "one cell per voxel holding material; about 60 bytes a voxel, 200 MB for the default "
                 "scenario) or none",
      .source = "sim/deposit_files.hpp",
      .choices = kFieldFormats},
     BT_MEMBER(OutputSpec, write_fields)},
    {{.key = "history_layers",
      .default_text = "[0, 14, 29]",
      .range = {0, 100000},
      .meaning = "a list of toolpath layers (numbered from 0 at the table, as in the report's layer table) "
                 "whose mean temperature against time report.html plots and report.json keeps "
                 "(temperature_history), every thermal.sample_interval; layers the print does not reach "
                 "are left out; [] for none. The default is the 1st, 15th and 30th layer",
      .source = "scenarios/report_html.cpp"},
     BT_MEMBER(OutputSpec, history_layers)},
};

const Param<ThermalSpec> kThermal[] = {
    {{.key = "cells_across",
      .default_text = "3",
      .range = {1, 15},
      .meaning = "thermal cells across a bead, odd: a centre and two edges at 3",
      .source = "thermal/mesh.hpp"},
     BT_MEMBER(ThermalSpec, cells_across)},
    {{.key = "cells_through",
      .default_text = "1",
      .range = {1, 15},
      .meaning = "thermal cells through a bead's height",
      .source = "thermal/mesh.hpp"},
     BT_MEMBER(ThermalSpec, cells_through)},
    {{.key = "cell_length",
      .dim = D::kLength,
      .range = {.min = 0, .max = 1e5, .min_exclusive = true},
      .meaning = "thermal cell length along a bead; absent: two bead widths, made longer (with a note) "
                 "where that would be more than 250,000 cells",
      .source = "thermal/mesh.hpp",
      .derived = true},
     BT_MEMBER(ThermalSpec, cell_length_mm)},
    {{.key = "birth_interval",
      .dim = D::kTime,
      .range = {.min = 0, .max = 1e4, .min_exclusive = true},
      .meaning = "cells laid within this time are born together; absent: a fifth of the beads' median "
                 "conduction time constant, made longer (with a note) where the print would need more than "
                 "5,000 birth events",
      .source = "thermal/heat.hpp",
      .derived = true},
     BT_MEMBER(ThermalSpec, birth_interval_s)},
    {{.key = "cooldown",
      .dim = D::kTime,
      .default_text = "10 min",
      .range = {0, 1e7},
      .meaning = "time simulated after the last layer: the layers' temperature history, the final "
                 "temperatures and the energy balance end there; healing goes on past it while an "
                 "interface is at or above its healing threshold (thermal.max_cooldown)"},
     BT_MEMBER(ThermalSpec, cooldown_s)},
    {{.key = "max_cooldown",
      .dim = D::kTime,
      .default_text = "24 h",
      .range = {0, 1e7},
      .meaning = "longest time after the last layer that healing is followed while an interface is still "
                 "at or above its healing threshold; those still there then are reported "
                 "(interfaces.still_warm_fraction)",
      .source = "thermal/heat.hpp"},
     BT_MEMBER(ThermalSpec, max_cooldown_s)},
    {{.key = "sample_interval",
      .dim = D::kTime,
      .default_text = "5 s",
      .range = {.min = 0, .max = 1e5, .min_exclusive = true},
      .meaning = "how often the layers' temperatures are kept for the history plots"},
     BT_MEMBER(ThermalSpec, sample_interval_s)},
    {{.key = "snapshots",
      .dim = D::kTime,
      .range = {0, 1e7},
      .meaning = "times [t, ...] (or `end`, the end of the print) at which every cell's temperature is "
                 "written: temperature-<t>s.vdb (voxels) and .vtp (cell centroids, ParaView); absent: none",
      .source = "thermal/snapshot_files.hpp",
      .derived = true,
      .form = "list of times, or end"}},
    {{.key = "rel_tol",
      .default_text = "1e-3",
      .range = {.min = 0, .max = 0.1, .min_exclusive = true},
      .meaning = "CVODE relative tolerance"},
     BT_MEMBER(ThermalSpec, rel_tol)},
    {{.key = "abs_tol",
      .default_text = "0.05",
      .range = {.min = 0, .max = 10, .min_exclusive = true},
      .meaning = "CVODE absolute tolerance, kelvin"},
     BT_MEMBER(ThermalSpec, abs_tol_k)},
    {{.key = "lump",
      .default_text = "true",
      .meaning = "lump settled cells (more than 20 contacts below the top, within 0.5 K along the bead) "
                 "into one cell per run, with a note, and a bead's slices through its height into one cell "
                 "once two beads lie over it: a long print's old layers then cost little in each step; "
                 "false: keep every cell",
      .source = "docs/physics.md"},
     BT_MEMBER(ThermalSpec, lump)},
    {{.key = "view_factors",
      .default_text = "true",
      .meaning = "each open face radiates with its view factors of the sky and the table, from rays traced "
                 "against the part as laid so far (the rest of its view sees the part: no net exchange); "
                 "false: every open face radiates to the air over its whole hemisphere",
      .source = "docs/physics.md"},
     BT_MEMBER(ThermalSpec, view_factors)},
    {{.key = "uncertainty",
      .default_text = "off",
      .meaning = "the P10-P90 band of every interface's substrate and surface temperature and healing over "
                 "the plausible ranges its material and machine files give (ranges), and its verdict at "
                 "both ends (marginal where they differ): linearised (one more heat solve per heat input "
                 "with a range, run two at a time; the healing law's inputs cost no solve: about 8 times the "
                 "thermal stage's time) or off",
      .source = "docs/physics.md (uncertainty of the verdicts)"},
     BT_MEMBER(ThermalSpec, uncertainty)},
    {{.key = "uncertainty_tolerance",
      .default_text = "1",
      .range = {.min = 1, .max = 100},
      .meaning = "the bands' extra heat solves run at rel_tol and abs_tol times this (rel_tol at most 0.1): "
                 "cheaper, at the cost of the band's accuracy",
      .source = "docs/physics.md (uncertainty of the verdicts)"},
     BT_MEMBER(ThermalSpec, uncertainty_tolerance)},
};

const Param<RenderSpec> kRender[] = {
    {{.key = "width",
      .default_text = "1280",
      .range = {16, 8192},
      .meaning = "width of the pictures, pixels"},
     BT_MEMBER(RenderSpec, width)},
    {{.key = "height",
      .default_text = "800",
      .range = {16, 8192},
      .meaning = "height of the pictures, pixels"},
     BT_MEMBER(RenderSpec, height)},
    {{.key = "samples",
      .default_text = "8",
      .range = {1, 1024},
      .meaning = "rays per pixel (stratified): smoother edges, shadows and occlusion for more time",
      .source = "render/render.hpp"},
     BT_MEMBER(RenderSpec, samples)},
    {{.key = "ambient_occlusion",
      .default_text = "true",
      .meaning = "darken the grooves between beads and layers by the sky they cannot see, so ridges and "
                 "layer lines read",
      .source = "render/render.hpp"},
     BT_MEMBER(RenderSpec, ambient_occlusion)},
    {{.key = "legend",
      .default_text = "true",
      .meaning = "a title, a legend with the colour scale and its unit, and a scale bar on every picture",
      .source = "render/annotate.hpp"},
     BT_MEMBER(RenderSpec, legend)},
    {{.key = "exr",
      .default_text = "false",
      .meaning = "each picture also as OpenEXR: linear RGB and a channel of the coloured quantity's raw "
                 "value per pixel (NaN off the part), and depth",
      .source = "render/image.hpp"},
     BT_MEMBER(RenderSpec, exr)},
    {{.key = "sheet",
      .default_text = "true",
      .meaning = "a comparison sheet per picture: the variants side by side, same camera, same colour "
                 "scale"},
     BT_MEMBER(RenderSpec, sheet)},
    {{.key = "images",
      .meaning = "the pictures of every variant, a list of maps (keys in the next table); without it: "
                 "fusion from the isometric and top views, sections, substrate temperature and, with a "
                 "part mesh, the deviation",
      .derived = true,
      .form = "list of maps"}},
    {{.key = "progress",
      .default_text = "none",
      .meaning = "a picture per layer as the part grows, for a video: a map {colour, view, every} (keys as "
                 "for an image, every: 1 takes every layer), or none",
      .form = "none, or a map"}},
};

// An image's own keys; its view is camera_params().
const Param<ImageSpec> kImage[] = {
    {{.key = "name",
      .meaning =
          "file name without extension, unique among the pictures; default: the colouring and the view",
      .derived = true,
      .form = "text"}},
    {{.key = "colour",
      .meaning = "what colours the part: fusion (verdict), section, layer, time (of deposition), substrate "
                 "(temperature of what a bead landed on), surface (its surface's, as a thermal camera reads "
                 "it before "
                 "the bead covers it), healing (least degree of healing), deviation (stock over "
                 "the CAD), porosity (local void fraction) or temperature (at `time`)",
      .source = "docs/physics.md"},
     BT_MEMBER(ImageSpec, colour)},
    {{.key = "cut.point",
      .dim = D::kLength,
      .meaning =
          "a cutaway: a point of the cutting plane [x, y, z]; the inside shows where the plane cuts the part",
      .derived = true,
      .form = "[x, y, z] length"}},
    {{.key = "cut.normal",
      .default_text = "[0, -1, 0]",
      .meaning = "the cutting plane's normal [x, y, z]: the half it points into is taken away",
      .form = "[x, y, z] number"}},
    {{.key = "layer",
      .range = {0, 1e7},
      .meaning = "the part as it stood when this toolpath layer (from 0) was done; default the finished part",
      .derived = true},
     BT_MEMBER(ImageSpec, up_to_layer)},
    {{.key = "time",
      .dim = D::kTime,
      .range = {0, 1e9},
      .meaning = "colour temperature: the moment, from the start of the print; default its end",
      .derived = true},
     BT_MEMBER(ImageSpec, time_s)},
    {{.key = "range",
      .meaning = "the colour scale's ends [low, high], in the colouring's unit (°C, s, mm, fraction, layer); "
                 "default "
                 "the data's range",
      .derived = true,
      .form = "[low, high]"}},
};

// The view of an image or of the progress frames.
const Param<render::CameraSpec> kCamera[] = {
    {{.key = "view",
      .default_text = "isometric",
      .meaning = "isometric, top, front (from -y), side (from +x), or user (the camera keys)"},
     BT_MEMBER(render::CameraSpec, view)},
    {{.key = "camera.position",
      .dim = D::kLength,
      .meaning = "user view: the eye [x, y, z]; without it the camera looks along camera.direction, framed "
                 "on the part",
      .derived = true},
     BT_MEMBER(render::CameraSpec, position)},
    {{.key = "camera.target",
      .dim = D::kLength,
      .meaning = "user view: the point looked at [x, y, z]; default the part's centre",
      .derived = true},
     BT_MEMBER(render::CameraSpec, target)},
    {{.key = "camera.direction",
      .default_text = "[-1, 1, -1]",
      .meaning = "user view without a position: the viewing direction [x, y, z]",
      .nonzero = true},
     BT_MEMBER(render::CameraSpec, direction)},
    {{.key = "field_of_view",
      .dim = D::kAngle,
      .default_text = "30 deg",
      .range = {0, 120},
      .meaning =
          "perspective angle of the isometric and user views across the picture's shorter side; 0 draws them "
          "orthographic (otherwise at least 1 deg). Top, front and side are always orthographic"},
     BT_MEMBER(render::CameraSpec, field_of_view_deg)},
};

const Param<ProgressSpec> kProgress[] = {
    {{.key = "colour",
      .default_text = "layer",
      .meaning = "what colours the part in the frames, as for an image"},
     BT_MEMBER(ProgressSpec, colour)},
    {{.key = "every", .default_text = "1", .range = {1, 100000}, .meaning = "a frame every this many layers"},
     BT_MEMBER(ProgressSpec, every)},
};

}  // namespace

std::span<const Param<Scenario>> scenario_params() {
  return kScenario;
}
std::span<const Param<PartSpec>> part_params() {
  return kPart;
}
std::span<const Param<Tool>> tool_params() {
  return kTool;
}
std::span<const Param<OutputSpec>> output_params() {
  return kOutput;
}
std::span<const Param<ThermalSpec>> thermal_params() {
  return kThermal;
}
std::span<const Param<RenderSpec>> render_params() {
  return kRender;
}
std::span<const Param<ImageSpec>> image_params() {
  return kImage;
}
std::span<const Param<render::CameraSpec>> camera_params() {
  return kCamera;
}
std::span<const Param<ProgressSpec>> progress_params() {
  return kProgress;
}

}  // namespace beadtwin::scenarios

namespace beadtwin::scenarios {
namespace {

template <class B>
void table(std::string& out, std::string_view title, std::string_view intro,
           std::span<const Param<B>> params) {
  out += fmt::format("\n## {}\n\n{}\n\n", title, intro);
  out += "| key | type | default | range | meaning | source |\n|---|---|---|---|---|---|\n";
  for (const Param<B>& p : params) {
    const std::string def = !p.default_text.empty() ? fmt::format("`{}`", p.default_text)
                            : p.derived             ? "derived"
                                                    : "required";
    const std::vector<std::string_view> spellings = p.spellings();
    out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", p.key,
                       param_type_text(p, p.shape(), p.member.point_size(), spellings), def,
                       param_range_text(p, p.shape()), p.meaning, p.source);
  }
}

}  // namespace

std::string params_markdown() {
  std::string out =
      "# Scenario parameters\n\n"
      "Generated by `beadtwin params` from the declarations the scenario loader reads, so it cannot\n"
      "drift from what beadtwin accepts. Quantities take a unit (`0.83 in`, `5 mm`, `240 C`, `150 lb/h`,\n"
      "`45 deg`, `10 %`); a bare number takes the file's `units:` default, else the internal unit the range "
      "is\n"
      "given in. A dotted key is a nested map: `boundary.passes: 2` is written `boundary: {passes: 2}`.\n";
  table(out, "Scenario", "The top level of a scenario file.", scenario_params());
  table(out, "Sections", "Each entry of `sections:`; a variant sets them as `sections.<name>.<key>`.",
        slicer::section_params());
  table(out, "Machine", "A file in `machines/` (or an inline `machine:` map); variants set `machine.<key>`.",
        machine_params());
  table(out, "Material",
        "A file in `materials/` (or an inline `material:` map); variants set `material.<key>`.",
        material_params());
  table(out, "Part", "The `part:` map: exactly one of `mesh`, `box` or `open_box`.", part_params());
  table(out, "Tools (melt configurations)",
        "Each entry of the `tools:` map, by name; sections refer to one with `tool: <name>`.", tool_params());
  table(out, "Output", "The `output:` block.", output_params());
  table(out, "Thermal solver", "The `thermal:` block.", thermal_params());
  table(out, "Pictures", "The `render:` block.", render_params());
  table(out, "Pictures: each image", "Each entry of `render.images:`, with the view keys of the next table.",
        image_params());
  table(out, "Pictures: the view", "The view of an image, and of the progress frames.", camera_params());
  table(out, "Pictures: progress frames",
        "The `render.progress:` map, with the view keys of the table above.", progress_params());
  return out;
}

}  // namespace beadtwin::scenarios
