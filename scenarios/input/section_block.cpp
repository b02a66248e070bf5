// A scenario's section: its keys read through the slicer's declaration (slicer/section_params.hpp), then
// what depends on other keys or on the rest of the scenario: the Z extent (limits, `part`, or a number of
// layers), the bead (given, or from a tool), the speeds (matched to the extruder where not given), and the
// checks across keys.
#include <set>

#include <fmt/format.h>

#include "core/bead.hpp"
#include "scenarios/input/scenario_blocks.hpp"
#include "slicer/section_params.hpp"

namespace beadtwin::scenarios {
namespace {

using Given = std::set<std::string_view>;

// A section's whole part (or its body) laid on its slice plane.
slicer::TriangleMesh section_part(const slicer::SectionParams& s, const slicer::TriangleMesh& part) {
  const int body = s.body.empty() ? -1 : slicer::find_body(part, s.body);
  return slicer::lay_down(body < 0 ? part : slicer::select_body(part, body), s.slice_plane);
}

void check_body(BlockReader& r, const slicer::SectionParams& s, const Given& given,
                const slicer::TriangleMesh& part) {
  if (!given.contains("body")) return;
  if (s.body.empty()) r.fail(r.take("body"), "body", "expected the name of one of the part's bodies");
  if (slicer::find_body(part, s.body) < 0)
    r.fail(
        r.take("body"), "body",
        fmt::format("the part has no body named '{}'; its bodies are: {}", s.body, slicer::body_list(part)));
}

// AM Outline (patent (39)) and its variable layer height (seed 002); containment boundaries (patent (41))
// as the union of what was given.
void check_outline(BlockReader& r, slicer::SectionParams& s, const Given& given) {
  if (s.outline_path.empty() &&
      (given.contains("variable_height.slope") || given.contains("variable_height.direction")))
    r.fail(r.take("variable_height"), "variable_height",
           "a variable layer height needs an AM Outline section (outline: points)");
  if (!s.containment_outside.empty()) s.containment_outside = slicer::union_nonzero(s.containment_outside);
  if (!s.containment_inside.empty()) s.containment_inside = slicer::union_nonzero(s.containment_inside);
  if (given.contains("shares_wall_with") && s.shares_wall_with.empty())
    r.fail(r.take("shares_wall_with"), "shares_wall_with", "expected the name of another section");
}

// The tool a section names, or null.
const Tool* section_tool(BlockReader& r, const std::map<std::string, Tool>& tools) {
  const YAML::Node tn = r.take("tool");
  if (!tn.IsDefined()) return nullptr;
  const auto found = tn.IsScalar() ? tools.find(tn.Scalar()) : tools.end();
  if (found == tools.end()) {
    std::string names;
    for (const auto& [n, _] : tools) names += (names.empty() ? "" : ", ") + n;
    r.fail(tn, "tool",
           fmt::format("no tool named '{}' under tools: (there are: {})", tn.IsScalar() ? tn.Scalar() : "?",
                       names.empty() ? "none" : names));
  }
  return &found->second;
}

// The bead: the section's own, else its tool's (patent (48)), else the declared defaults.
void read_bead(BlockReader& r, slicer::SectionParams& s, const Given& given, const SectionContext& c) {
  if (const Tool* tool = section_tool(r, c.tools)) {
    if (!given.contains("layer_height")) s.layer_height_mm = tool->bead_thickness_mm;
    if (!given.contains("bead_width")) s.bead_width_mm = tool->bead_width_mm;
  }
  if (s.bead_width_mm < s.layer_height_mm)
    r.fail(r.take("bead_width"), "bead_width",
           fmt::format("bead width {} mm is less than the layer height {} mm", s.bead_width_mm,
                       s.layer_height_mm));
}

// Z limits [lower, upper], `part` for the whole part (or body), or a number of layers (AM Outline).
void read_extent(BlockReader& r, slicer::SectionParams& s, const SectionContext& c) {
  const YAML::Node z = r.take("z");
  const YAML::Node layers = r.take("layers");
  if (!z.IsDefined() && !(layers.IsDefined() && !s.outline_path.empty()))
    r.fail(
        z, "z",
        "required key is missing (Z limits [lower, upper], or 'part'; an outline section may give layers)");
  if (z.IsDefined() && layers.IsDefined()) r.fail(layers, "layers", "give either z or layers, not both");
  if (layers.IsDefined()) {
    const ParamValue n =
        r.value(layers, find_param(slicer::section_params(), "layers"), ParamShape::kInteger, 0, {});
    s.z_min_mm = 0.0;
    s.z_max_mm = static_cast<double>(n.integer()) * s.layer_height_mm;
  } else if (z.IsScalar() && z.Scalar() == "part") {
    const slicer::TriangleMesh m = section_part(s, c.part);
    s.z_min_mm = m.min_corner().z();
    s.z_max_mm = m.max_corner().z();
  } else {
    if (!z.IsSequence() || z.size() != 2) r.fail(z, "z", "expected Z limits [lower, upper] or 'part'");
    s.z_min_mm = r.parse(z[0], Dimension::kLength, "z");
    s.z_max_mm = r.parse(z[1], Dimension::kLength, "z");
    if (!(s.z_max_mm > s.z_min_mm))
      r.fail(z, "z", fmt::format("upper limit {} mm is not above lower limit {} mm", s.z_max_mm, s.z_min_mm));
  }
  constexpr double kMaxLayers = 20000;  // a 3 m part at 0.15 mm: far beyond any real section
  const double count = (s.z_max_mm - s.z_min_mm) / s.layer_height_mm;
  if (count > kMaxLayers)
    r.fail(r.has("layer_height") ? r.take("layer_height") : YAML::Node(), "layer_height",
           fmt::format("{} mm layers over {} mm make {:.0f} layers; at most {:.0f} are allowed",
                       s.layer_height_mm, s.z_max_mm - s.z_min_mm, count, kMaxLayers));
}

// The speeds a section leaves out: printing matched to the extruder's nominal output (v = Q / A), travel at
// the machine's most; a print speed the extruder cannot feed is refused.
void resolve_speeds(BlockReader& r, slicer::SectionParams& s, const Given& given, const SectionContext& c) {
  const double area = bead_area_mm2(s.bead_width_mm, s.layer_height_mm);
  const double density = c.material.density_kg_m3;
  if (!given.contains("speed")) s.print_speed_mm_s = c.machine.extruder_output_kg_s / density * 1e9 / area;
  const double max_flow_mm3_s = c.machine.extruder_max_output_kg_s / density * 1e9;
  if (s.print_speed_mm_s * area > max_flow_mm3_s * (1 + 1e-9))
    r.fail(r.take("speed"), "speed",
           fmt::format("needs {:.0f} mm3/s of material but the extruder gives at most {:.0f} mm3/s",
                       s.print_speed_mm_s * area, max_flow_mm3_s));
  if (!given.contains("travel_speed")) s.travel_speed_mm_s = c.machine.motion.max_travel_mm_s;
}

// fill: none | {style, angle, ...}: the fill keys are read (with their defaults) either way; the overlaps
// with the boundary default to the pass overlap.
void read_fill(BlockReader& r, slicer::SectionParams& s, const Given& given) {
  const YAML::Node fill = r.take("fill");
  const bool off = fill.IsDefined() && fill.IsScalar() && (fill.Scalar() == "none" || fill.Scalar() == "off");
  if (fill.IsDefined() && !fill.IsMap() && !off)
    r.fail(fill, "fill", "expected 'none' or a map {style, angle, angle_step, overlap, ...}");
  slicer::FillParams& f = s.fill;
  f.enabled = fill.IsDefined() && fill.IsMap();
  if (f.max_overlap < f.overlap)
    r.fail(r.take("fill.max_overlap"), "fill.max_overlap",
           fmt::format("maximum pass overlap {:.0f} % is below the pass overlap {:.0f} %",
                       100 * f.max_overlap, 100 * f.overlap));
  if (!given.contains("fill.boundary_overlap")) f.boundary_overlap = f.overlap;
  if (!given.contains("fill.boundary_side_overlap")) f.boundary_side_overlap = f.overlap;
}

void check_passes(BlockReader& r, const slicer::SectionParams& s) {
  if (s.boundary.max_overlap < s.boundary.overlap)
    r.fail(r.take("boundary.max_overlap"), "boundary.max_overlap",
           fmt::format("maximum pass overlap {:.0f} % is below the pass overlap {:.0f} %",
                       100 * s.boundary.max_overlap, 100 * s.boundary.overlap));
}

// A prime or reverse at a pump speed means nothing without the pump's displacement.
void check_melt(BlockReader& r, const slicer::SectionParams& s, const Machine& machine) {
  const MeltSettings& m = s.melt;
  if (!((m.prime && m.prime_rpm > 0) || (m.reverse && m.reverse_rpm > 0)) || machine.extruder.has_rpm())
    return;
  const char* key = m.prime ? "melt_on.prime_rpm" : "melt_off.reverse_rpm";
  r.fail(r.take(key), key,
         fmt::format("machine '{}' gives no extruder displacement (extruder.displacement), so a speed in "
                     "rev/min means no flow",
                     machine.name));
}

}  // namespace

slicer::SectionParams read_section(BlockReader& r, const SectionContext& context) {
  const auto params = slicer::section_params();
  slicer::SectionParams s;
  const Given given = r.read(params, s);
  check_body(r, s, given, context.part);
  check_outline(r, s, given);
  read_bead(r, s, given, context);
  read_extent(r, s, context);
  resolve_speeds(r, s, given, context);
  check_passes(r, s);
  check_melt(r, s, context.machine);
  read_fill(r, s, given);
  r.finish(params);
  return s;
}

}  // namespace beadtwin::scenarios
