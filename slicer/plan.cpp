#include "slicer/plan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "slicer/boundary.hpp"
#include "slicer/fill.hpp"
#include "slicer/layer_builder.hpp"
#include "slicer/polygons.hpp"
#include "slicer/slice.hpp"

namespace beadtwin::slicer {
namespace {

// The region a layer of section `s` fills at height `z_mid`, after the toolpath parameters that change it.
Polygons layer_region(const TriangleMesh& mesh, const SectionParams& s, double z_mid, PlanStats& stats) {
  SliceStats slice_stats;
  Polygons region = slice_mesh(mesh, z_mid, &slice_stats);
  stats.open_chains += slice_stats.open_chains;
  if (s.merge_slices) {
    // Merge slices for extra stock: the largest outline of the previous, this and the next layer.
    for (const double dz : {-s.layer_height_mm, s.layer_height_mm}) {
      Polygons other = slice_mesh(mesh, z_mid + dz);
      if (area_mm2(other) > area_mm2(region)) region = std::move(other);
    }
  }
  region = drop_small(simplify(region, s.chord_tolerance_mm), s.min_polygon_area_mm2);
  if (s.shift_mm != Eigen::Vector2d::Zero())
    for (Polygon& poly : region)
      for (Eigen::Vector2d& p : poly) p += s.shift_mm;
  Polygons outers, holes;
  split_contours(region, outers, holes);
  if (s.ignore_inner_contours) holes.clear();
  if (s.outer_stock_mm != 0.0) outers = offset(outers, s.outer_stock_mm);
  if (!holes.empty()) {
    // Holes as regions of their own (counter-clockwise), shrunk by the inner stock, cut out of the outers.
    for (Polygon& h : holes) std::reverse(h.begin(), h.end());
    if (s.inner_stock_mm != 0.0) holes = offset(holes, -s.inner_stock_mm);
    return difference(outers, holes);
  }
  return union_nonzero(outers);
}

// One layer: the boundary passes and (where enabled, or forced for rafts) the fill, in the section's layer
// order. `role` marks raft and stock-on-top layers. `angle_index` turns the fill and moves the seam.
void lay_layer(Toolpath& tp, const SectionParams& s, int section, const Polygons& region, double z_top,
               int angle_index, Feature role, bool fill, Eigen::Vector2d& head) {
  const int layer = static_cast<int>(tp.layers.size());
  ToolpathLayer info;
  info.z_mm = z_top;
  info.height_mm = s.layer_height_mm;
  info.section = section;
  info.outline_area_mm2 = area_mm2(region);
  info.outline_perimeter_mm = perimeter_mm(region);
  tp.layers.push_back(info);

  const double w = s.bead_width_mm;
  const double pitch = w * (1.0 - s.boundary.overlap);
  if (s.clearance_height_mm > 0 && !tp.moves.empty()) {
    // Clearance between layers: straight up, then across at the clearance height.
    const double zc = std::max(s.clearance_height_mm, z_top);
    const Eigen::Vector3d from = tp.moves.back().end;
    Move up;
    up.kind = MoveKind::kTravel;
    up.feature = Feature::kTravel;
    up.section = section;
    up.layer = layer;
    up.feed_mm_s = s.travel_speed_mm_s;
    up.start = from;
    up.end = {from.x(), from.y(), std::max(zc, from.z())};
    if ((up.end - up.start).norm() > 1e-9) tp.moves.push_back(up);
  }
  LayerBuilder b(tp, s, section, layer, z_top, head, role);

  // Boundary passes: pass k runs along the outline offset inward by w/2 + k·pitch.
  std::vector<Polygons> passes;
  for (int k = 0; k < s.boundary.passes; ++k) {
    Polygons loops = offset(region, -(0.5 * w + k * pitch));
    if (loops.empty()) break;
    passes.push_back(std::move(loops));
  }
  // The fill's bead centres stay w/2 − overlap·w inside the last boundary bead's inner edge, which works out
  // to the offset the next boundary pass would have had.
  const Polygons fill_region =
      fill ? offset(region, -(0.5 * w + static_cast<double>(passes.size()) * pitch)) : Polygons{};
  if (s.fill_first) lay_fill(b, s, fill_region, angle_index);
  lay_boundary(b, s, passes, angle_index);
  if (s.boundary.thin_walls) lay_thin_walls(b, s, region);
  if (!s.fill_first) lay_fill(b, s, fill_region, angle_index);
}

// One layer to lay: where, for which section, with what outline and role.
struct LayerJob {
  double z_top_mm = 0.0;
  int section = 0;
  int order = 0;  // the section's place in Z order: breaks ties at equal heights
  Polygons region;
  int angle_index = 0;  // layers laid before it in its section: turns the fill and moves the seam
  Feature role = Feature::kUnknown;
  bool fill = false;
  bool outline = false;  // an AM Outline layer: the section's own path, not a slice
};

// Every layer of one section, with its rafts below and its stock on top, shifted up by `z_shift_mm`.
void section_jobs(const TriangleMesh& mesh, const SectionParams& s, int section, int order, double z_shift_mm,
                  std::vector<LayerJob>& jobs, PlanStats& stats) {
  const int layers = static_cast<int>(std::floor((s.z_max_mm - s.z_min_mm) / s.layer_height_mm + 1e-6));
  const double h = s.layer_height_mm;
  int index = 0;
  std::optional<std::size_t> last_at;  // the section's top layer among the jobs
  for (int l = 0; l < layers; ++l) {
    const double z_cad = s.z_min_mm + (l + 1) * h;
    Polygons region = layer_region(mesh, s, z_cad - 0.5 * h, stats);
    if (region.empty()) {
      ++stats.empty_layers;
      continue;
    }
    if (index == 0) {
      // Rafts: solid layers with the first layer's outline; the part sits on them (z_shift_mm includes them).
      for (int r = 0; r < s.rafts; ++r)
        jobs.push_back(
            {z_cad - (s.rafts - r) * h + z_shift_mm, section, order, region, index++, Feature::kRaft, true});
    }
    jobs.push_back(
        {z_cad + z_shift_mm, section, order, std::move(region), index++, Feature::kUnknown, s.fill.enabled});
    last_at = jobs.size() - 1;
  }
  // Stock on top: solid layers on the section's top layer, with its outline.
  if (!last_at) return;
  const Polygons top = jobs[*last_at].region;
  const double top_z = jobs[*last_at].z_top_mm;
  for (int t = 0; t < s.stock_on_top; ++t)
    jobs.push_back({top_z + (t + 1) * h, section, order, top, index++, Feature::kStockOnTop, true});
}

// AM Outline: every layer of the section prints its 2-D path (patent (39)).
void outline_jobs(const SectionParams& s, int section, int order, double z_shift_mm,
                  std::vector<LayerJob>& jobs) {
  const int layers = static_cast<int>(std::floor((s.z_max_mm - s.z_min_mm) / s.layer_height_mm + 1e-6));
  for (int l = 0; l < layers; ++l) {
    LayerJob j;
    j.z_top_mm = s.z_min_mm + (l + 1) * s.layer_height_mm + z_shift_mm;
    j.section = section;
    j.order = order;
    j.angle_index = l;
    j.outline = true;
    jobs.push_back(std::move(j));
  }
}

void lay_outline(Toolpath& tp, const SectionParams& s, int section, double z_top, int index,
                 Eigen::Vector2d& head) {
  Polygon path = s.outline_path;
  for (Eigen::Vector2d& p : path) p += s.shift_mm;
  const double length =
      s.outline_closed ? perimeter_mm({path}) : perimeter_mm({path}) - (path.back() - path.front()).norm();
  ToolpathLayer info;
  info.z_mm = z_top;
  info.height_mm = s.layer_height_mm;
  info.section = section;
  info.outline_area_mm2 = length * s.bead_width_mm;  // the bead's footprint
  info.outline_perimeter_mm = 2.0 * length;
  const int layer = static_cast<int>(tp.layers.size());
  tp.layers.push_back(info);
  LayerBuilder b(tp, s, section, layer, z_top, head, Feature::kUnknown);
  if (s.boundary.reverse_alternate && index % 2 == 1) std::reverse(path.begin(), path.end());
  if (s.outline_closed) {
    b.print_pass(start_at(path, s.start_point_mm, index * s.seam_offset_mm), 0, s.boundary.lead_in_mm,
                 s.boundary.lead_out_mm, s.boundary.start_stop_overlap * s.bead_width_mm,
                 s.boundary.tangential_lead_out);
    return;
  }
  // Open toolpath start (patent (43)): from whichever end is nearer the start point (before the alternating
  // reversal, which then runs every other layer back).
  const bool from_far_end =
      (s.outline_path.back() - s.start_point_mm).norm() < (s.outline_path.front() - s.start_point_mm).norm();
  if (from_far_end) std::reverse(path.begin(), path.end());
  b.print_open(path, 0, s.boundary.lead_in_mm, s.boundary.lead_out_mm);
}

// The mesh a section slices: the whole part, or the one body it names.
TriangleMesh section_mesh(const TriangleMesh& mesh, const SectionParams& s) {
  if (s.body.empty()) return mesh;
  const int body = find_body(mesh, s.body);
  if (body < 0)
    throw InputError(
        {}, "sections." + s.name + ".body",
        fmt::format("the part has no body named '{}'; its bodies are: {}", s.body, body_list(mesh)));
  return select_body(mesh, body);
}

void validate(const std::vector<SectionParams>& sections) {
  for (const auto& s : sections) {
    const std::string key = "sections." + s.name;
    if (!(s.layer_height_mm > 0)) throw InputError({}, key + ".layer_height", "must be positive");
    if (!(s.bead_width_mm >= s.layer_height_mm))
      throw InputError({}, key + ".bead_width",
                       fmt::format("must be at least the layer height ({} mm), got {} mm", s.layer_height_mm,
                                   s.bead_width_mm));
    if (!(s.z_max_mm > s.z_min_mm))
      throw InputError({}, key + ".z", "upper limit must be above the lower one");
    if (!(s.print_speed_mm_s > 0)) throw InputError({}, key + ".speed", "must be positive");
    if (s.boundary.passes < 0) throw InputError({}, key + ".boundary.passes", "must not be negative");
    if (!(s.boundary.overlap >= 0 && s.boundary.overlap < 0.5))
      throw InputError({}, key + ".boundary.overlap", "must be in [0, 50 %)");
    if (!(s.fill.overlap >= 0 && s.fill.overlap < 0.5))
      throw InputError({}, key + ".fill.overlap", "must be in [0, 50 %)");
  }
}

}  // namespace

Toolpath plan_toolpath(const TriangleMesh& mesh, const std::vector<SectionParams>& sections,
                       const MotionLimits& motion, PlanStats* stats) {
  validate(sections);
  std::vector<std::size_t> order(sections.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return sections[a].z_min_mm < sections[b].z_min_mm; });
  if (sections.empty()) throw InputError({}, "sections", "there is no section to plan");
  for (std::size_t i = 1; i < order.size(); ++i)
    if (sections[order[i]].rafts > 0)
      throw InputError({}, "sections." + sections[order[i]].name + ".rafts",
                       "rafts go under the lowest section only (they lift the whole part)");
  Toolpath tp;
  for (const auto& s : sections) tp.sections.push_back(s.name);
  PlanStats local;
  Eigen::Vector2d head = mesh.vertices.empty()
                             ? Eigen::Vector2d::Zero()
                             : Eigen::Vector2d(mesh.min_corner().x(), mesh.min_corner().y());
  // Rafts under the lowest section lift the whole part.
  const SectionParams& lowest = sections[order.front()];
  const double z_shift = lowest.rafts * lowest.layer_height_mm;
  std::vector<LayerJob> jobs;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const SectionParams& s = sections[order[i]];
    if (!s.outline_path.empty())
      outline_jobs(s, static_cast<int>(order[i]), static_cast<int>(i), z_shift + s.contact_offset_mm, jobs);
    else
      section_jobs(section_mesh(mesh, s), s, static_cast<int>(order[i]), static_cast<int>(i),
                   z_shift + s.contact_offset_mm, jobs, local);
  }
  // AM Z merge (patent (14), (39)): the layers of all sections in one program, by height, so sections side
  // by side rise together and an elevated section starts when the build reaches it (patent (16)).
  std::stable_sort(jobs.begin(), jobs.end(), [](const LayerJob& a, const LayerJob& b) {
    if (std::abs(a.z_top_mm - b.z_top_mm) > 1e-9) return a.z_top_mm < b.z_top_mm;
    return a.order < b.order;
  });
  for (const LayerJob& j : jobs) {
    if (j.outline) {
      lay_outline(tp, sections[static_cast<std::size_t>(j.section)], j.section, j.z_top_mm, j.angle_index,
                  head);
      continue;
    }
    lay_layer(tp, sections[static_cast<std::size_t>(j.section)], j.section, j.region, j.z_top_mm,
              j.angle_index, j.role, j.fill, head);
  }
  time_toolpath(tp, motion);
  if (stats) *stats = local;
  return tp;
}

}  // namespace beadtwin::slicer
