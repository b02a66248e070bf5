#include "slicer/plan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "core/bead.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "slicer/boundary.hpp"
#include "slicer/centre_beads.hpp"
#include "slicer/fill.hpp"
#include "slicer/layer_builder.hpp"
#include "slicer/melt_events.hpp"
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
  region =
      drop_small(simplify(region, s.chord_tolerance_mm, s.smoothing.smooth_curves), s.min_polygon_area_mm2);
  // Containment boundaries: the section's share of the part in the plane.
  if (!s.containment_outside.empty()) region = intersection(region, s.containment_outside);
  if (!s.containment_inside.empty()) region = difference(region, s.containment_inside);
  if (s.shift_mm != Eigen::Vector2d::Zero())
    for (Polygon& poly : region)
      for (Eigen::Vector2d& p : poly) p += s.shift_mm;
  Polygons outers, holes;
  split_contours(region, outers, holes);
  if (s.ignore_inner_contours) holes.clear();
  // Stock to leave: combined with the toolpath offset, one sharp-cornered offset; otherwise the stock
  // envelope at constant distance from the part (round at its convex corners), which the passes follow.
  auto stock = [&](const Polygons& p, double d) {
    return s.combine_stock_offset ? offset(p, d) : offset_round(p, d, 0.01 * s.bead_width_mm);
  };
  if (s.outer_stock_mm != 0.0) outers = stock(outers, s.outer_stock_mm);
  if (!holes.empty()) {
    // Holes as regions of their own (counter-clockwise), shrunk by the inner stock, cut out of the outers.
    for (Polygon& h : holes) std::reverse(h.begin(), h.end());
    if (s.inner_stock_mm != 0.0) holes = stock(holes, -s.inner_stock_mm);
    return difference(outers, holes);
  }
  return union_nonzero(outers);
}

// Beads laid since move `first`, as chains of equal width, in the plane.
std::vector<std::pair<std::vector<Polyline>, double>> laid_beads(const Toolpath& tp, std::size_t first) {
  std::vector<std::pair<std::vector<Polyline>, double>> out;
  Polyline chain;
  double width = 0.0;
  auto flush = [&] {
    if (chain.size() >= 2) {
      auto it = std::find_if(out.begin(), out.end(), [&](const auto& e) { return e.second == width; });
      if (it == out.end()) it = out.insert(out.end(), {{}, width});
      it->first.push_back(chain);
    }
    chain.clear();
  };
  for (std::size_t i = first; i < tp.moves.size(); ++i) {
    const Move& m = tp.moves[i];
    if (m.kind != MoveKind::kPrint || !m.deposits()) {
      flush();
      continue;
    }
    const Eigen::Vector2d a = m.start.head<2>(), b = m.end.head<2>();
    if (chain.empty() || m.bead_width_mm != width || (chain.back() - a).norm() > 1e-6) {
      flush();
      chain.push_back(a);
      width = m.bead_width_mm;
    }
    chain.push_back(b);
  }
  flush();
  return out;
}

// Void detection (patent (46)): the parts of `region` the beads laid since move `first` leave uncovered,
// wider than the section's minimum void width; counted in `stats` and, when asked, filled.
void find_voids(LayerBuilder& b, const SectionParams& s, const Polygons& region, std::size_t first,
                const Toolpath& tp, PlanStats& stats, bool fill) {
  Polygons covered;
  for (const auto& [chains, width] : laid_beads(tp, first)) covered = unite(covered, sweep(chains, width));
  const double min_width = s.voids.min_width_mm > 0 ? s.voids.min_width_mm : 0.25 * s.bead_width_mm;
  const Polygons voids = offset(offset(difference(region, covered), -0.5 * min_width), 0.5 * min_width);
  for (const Polygon& v : voids)
    if (area_mm2({v}) > 0) ++stats.voids_found;
  stats.void_area_mm2 += std::abs(area_mm2(voids));
  if (!fill) return;
  // A void gets beads of its own width down its middle: one up to the bead width, two side by side up to
  // twice it; wider voids are reported, not filled (they want fill passes, not a bead).
  CentreBeadRules rules;
  rules.min_width_mm = min_width;
  rules.max_width_mm = 2.0 * s.bead_width_mm;
  rules.one_bead_width_mm = s.bead_width_mm;
  stats.void_beads += lay_centre_beads(b, centre_beads(voids, covered, rules), Feature::kFill);
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
  Polygons shared_wall;  // the region of the section whose wall this one shares, at this height
  bool solid = false;    // a top or bottom surface layer: a sparse fill is laid solid
};

// One layer: the boundary passes and (where enabled, or forced for rafts) the fill, in the section's layer
// order, then the thin walls and void fill.
void lay_layer(Toolpath& tp, const SectionParams& s, const LayerJob& job, Eigen::Vector2d& head,
               PlanStats& stats) {
  const Polygons& region = job.region;
  const double z_top = job.z_top_mm;
  const int layer = static_cast<int>(tp.layers.size());
  ToolpathLayer info;
  info.z_mm = z_top;
  info.height_mm = s.layer_height_mm;
  info.section = job.section;
  info.outline_area_mm2 = area_mm2(region);
  info.outline_perimeter_mm = perimeter_mm(region);
  tp.layers.push_back(info);

  if (s.clearance_height_mm > 0 && !tp.moves.empty()) {
    // Clearance between layers: straight up, then across at the clearance height.
    const double zc = std::max(s.clearance_height_mm, z_top);
    const Eigen::Vector3d from = tp.moves.back().end;
    Move up;
    up.kind = MoveKind::kTravel;
    up.feature = Feature::kTravel;
    up.section = job.section;
    up.layer = layer;
    up.feed_mm_s = s.travel_speed_mm_s;
    up.start = from;
    up.end = {from.x(), from.y(), std::max(zc, from.z())};
    if ((up.end - up.start).norm() > 1e-9) tp.moves.push_back(up);
  }
  const std::size_t first = tp.moves.size();
  LayerBuilder b(tp, s, job.section, layer, z_top, head, job.role);
  const BoundaryPlan plan = plan_boundary(s, region, job.shared_wall, job.fill);
  if (job.role == Feature::kUnknown) {  // the plan holds one entry for each pass with room
    int& most = stats.most_passes_laid[static_cast<std::size_t>(job.section)];
    most = std::max(most, static_cast<int>(plan.loops.size()));
  }
  if (s.fill_first) lay_fill(b, s, plan.fill, job.angle_index, job.solid);
  lay_boundary(b, s, plan, job.angle_index);
  if (s.boundary.thin_walls) lay_thin_walls(b, s, region, plan);
  if (!s.fill_first) lay_fill(b, s, plan.fill, job.angle_index, job.solid);
  // Variable bead regions (patent (62)): the voids the fill leaves against the boundary get beads.
  const bool vbr = job.fill && s.fill.style == FillStyleKind::kVariableBeadRegions;
  if (s.voids.detect || s.voids.fill || vbr) find_voids(b, s, region, first, tp, stats, s.voids.fill || vbr);
}

// Whether the layer between z0 and z1 holds a top or bottom surface of the part (patent (65)): faces within
// the fill's angle tolerance of horizontal, in that height band, wider than the step tolerance across.
bool surface_layer(const TriangleMesh& mesh, const SectionParams& s, double z0, double z1) {
  const double cos_tol = std::cos(s.fill.angle_tolerance_deg * kPi / 180.0);
  Polygons flat;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d b = mesh.vertices[static_cast<std::size_t>(t[1])];
    const Eigen::Vector3d c = mesh.vertices[static_cast<std::size_t>(t[2])];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() <= 0 || std::abs(n.z()) < cos_tol * n.norm()) continue;
    const double zc = (a.z() + b.z() + c.z()) / 3.0;
    if (zc < z0 - 1e-6 || zc > z1 + 1e-6) continue;
    Polygon tri = {a.head<2>(), b.head<2>(), c.head<2>()};
    if (area_mm2({tri}) < 0) std::reverse(tri.begin(), tri.end());
    flat.push_back(std::move(tri));
  }
  if (flat.empty()) return false;
  const double step = s.fill.step_tolerance_mm > 0 ? s.fill.step_tolerance_mm : s.bead_width_mm;
  return !offset(offset(union_nonzero(flat), -0.5 * step), 0.5 * step).empty();
}

// A section as the planner slices it: its parameters and the mesh it slices.
struct Sliced {
  const SectionParams* params = nullptr;
  TriangleMesh mesh;
};

// Every layer of one section, with its rafts below and its stock on top, shifted up by `z_shift_mm`. With
// `wall` (the section whose wall this one shares), each layer carries that section's region at its height.
void section_jobs(const TriangleMesh& mesh, const SectionParams& s, int section, int order, double z_shift_mm,
                  const Sliced* wall, std::vector<LayerJob>& jobs, PlanStats& stats) {
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
    // A layer of the section; rafts and stock on top are solid layers with an outline of the section's.
    auto job = [&](double z_top, Polygons outline, Feature role, bool fill) {
      LayerJob j;
      j.z_top_mm = z_top;
      j.section = section;
      j.order = order;
      j.region = std::move(outline);
      j.angle_index = index++;
      j.role = role;
      j.fill = fill;
      j.solid = role != Feature::kUnknown;
      return j;
    };
    if (index == 0) {
      // Rafts: solid layers with the first layer's outline; the part sits on them (z_shift_mm includes them).
      for (int r = 0; r < s.rafts; ++r)
        jobs.push_back(job(z_cad - (s.rafts - r) * h + z_shift_mm, region, Feature::kRaft, true));
    }
    jobs.push_back(job(z_cad + z_shift_mm, std::move(region), Feature::kUnknown, s.fill.enabled));
    if (s.fill.enabled && s.fill.style == FillStyleKind::kSparseZigzag && !s.fill.sparse_fill_gaps)
      jobs.back().solid = surface_layer(mesh, s, z_cad - h, z_cad);
    if (wall) {
      PlanStats ignored;  // the other section counts its own slices
      jobs.back().shared_wall = layer_region(wall->mesh, *wall->params, z_cad - 0.5 * h, ignored);
    }
    last_at = jobs.size() - 1;
  }
  // Stock on top: solid layers on the section's top layer, with its outline.
  if (!last_at) return;
  const Polygons top = jobs[*last_at].region;
  const double top_z = jobs[*last_at].z_top_mm;
  for (int t = 0; t < s.stock_on_top; ++t) {
    LayerJob j;
    j.z_top_mm = top_z + (t + 1) * h;
    j.section = section;
    j.order = order;
    j.region = top;
    j.angle_index = index++;
    j.role = Feature::kStockOnTop;
    j.fill = true;
    j.solid = true;
    jobs.push_back(std::move(j));
  }
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

void lay_outline_path(Toolpath& tp, const SectionParams& s, int section, double z_top, int index,
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

// Variable layer height (seed 002, eq. 12) on the moves of outline layer `index` from move `first`: each
// point's layer top rises to z_base + (index + 1)·h(p) with h(p) = h0 + slope·(p − origin)·dir, and each
// print move, cut into pieces short enough that h changes by at most 1 %, lays A(h) = π h²/4 + b_p h with
// the core width b_p = w − h0 at the speed that keeps the flow at A(h0)·v0.
void apply_height_gradient(Toolpath& tp, std::size_t first, const SectionParams& s, double z_top, int index,
                           const Eigen::Vector2d& origin) {
  const double h0 = s.layer_height_mm, b_p = s.bead_width_mm - h0;
  const Eigen::Vector2d dir = s.height_direction.normalized();
  const double z_base = z_top - (index + 1) * h0;
  auto height = [&](const Eigen::Vector3d& p) {
    return h0 + s.height_slope * (p.head<2>() - origin).dot(dir);
  };
  auto top = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(p.x(), p.y(), z_base + (index + 1) * height(p));
  };
  const double flow = (0.25 * kPi * h0 * h0 + b_p * h0) * s.print_speed_mm_s;  // Q, constant (eqs. 9-10)
  std::vector<Move> out(tp.moves.begin(), tp.moves.begin() + static_cast<std::ptrdiff_t>(first));
  for (std::size_t i = first; i < tp.moves.size(); ++i) {
    Move m = tp.moves[i];
    if (m.kind != MoveKind::kPrint) {
      // Travels and events follow the wedge's top where they are at the layer's height.
      if (std::abs(m.start.z() - z_top) < 1e-9) m.start = top(m.start);
      if (std::abs(m.end.z() - z_top) < 1e-9) m.end = top(m.end);
      out.push_back(m);
      continue;
    }
    const double dh = std::abs(height(m.end) - height(m.start));
    const int pieces = std::max(1, static_cast<int>(std::ceil(dh / (0.01 * h0))));
    // The melt setting's reduction (a retraced lead-out) carries over.
    const double scale = m.volume_mm3 / (bead_area_mm2(m.bead_width_mm, m.layer_height_mm) * m.length_mm());
    for (int k = 0; k < pieces; ++k) {
      Move piece = m;
      const Eigen::Vector3d a = m.start + (m.end - m.start) * (static_cast<double>(k) / pieces);
      const Eigen::Vector3d b = m.start + (m.end - m.start) * (static_cast<double>(k + 1) / pieces);
      const double h = height(0.5 * (a + b));
      if (!(h > 0))
        throw InputError({}, "sections." + s.name + ".variable_height",
                         "the bead's height falls to zero along the path");
      const double area = 0.25 * kPi * h * h + b_p * h;
      piece.start = top(a);
      piece.end = top(b);
      piece.layer_height_mm = h;
      piece.bead_width_mm = b_p + h;
      piece.feed_mm_s = flow / area;  // eq. 12: constant flow, the head slows as the bead grows
      piece.volume_mm3 = area * (b - a).head<2>().norm() * scale;
      out.push_back(piece);
    }
  }
  tp.moves = std::move(out);
}

void lay_outline(Toolpath& tp, const SectionParams& s, int section, double z_top, int index,
                 Eigen::Vector2d& head) {
  const std::size_t first = tp.moves.size();
  lay_outline_path(tp, s, section, z_top, index, head);
  if (s.height_slope == 0.0) return;
  // The wedge starts at the path's first point along the gradient.
  const Eigen::Vector2d dir = s.height_direction.normalized();
  Eigen::Vector2d origin = s.outline_path.front() + s.shift_mm;
  for (const Eigen::Vector2d& p : s.outline_path)
    if ((p + s.shift_mm).dot(dir) < origin.dot(dir)) origin = p + s.shift_mm;
  apply_height_gradient(tp, first, s, z_top, index, origin);
}

// The mesh a section slices: the whole part, or the one body it names, laid down on its slice plane.
TriangleMesh section_mesh(const TriangleMesh& mesh, const SectionParams& s) {
  if (s.body.empty()) return lay_down(mesh, s.slice_plane);
  const int body = find_body(mesh, s.body);
  if (body < 0)
    throw InputError(
        {}, "sections." + s.name + ".body",
        fmt::format("the part has no body named '{}'; its bodies are: {}", s.body, body_list(mesh)));
  return lay_down(select_body(mesh, body), s.slice_plane);
}

// The index of the section whose wall `s` shares, checked: another sliced section at the same layer height,
// with layers at the same heights.
std::optional<std::size_t> wall_provider(const std::vector<SectionParams>& sections, const SectionParams& s) {
  if (s.shares_wall_with.empty()) return std::nullopt;
  std::size_t provider = 0;
  if (const std::string problem = shared_wall_problem(sections, s, &provider); !problem.empty())
    throw InputError({}, "sections." + s.name + ".shares_wall_with", problem);
  return provider;
}

// Every value within its declared range (slicer/section_params.hpp), then what the ranges cannot say.
void validate(const std::vector<SectionParams>& sections) {
  for (const auto& s : sections) {
    check_section_ranges(s);
    const std::string key = "sections." + s.name;
    if (!(s.bead_width_mm >= s.layer_height_mm))
      throw InputError({}, key + ".bead_width",
                       fmt::format("must be at least the layer height ({} mm), got {} mm", s.layer_height_mm,
                                   s.bead_width_mm));
    if (!(s.z_max_mm > s.z_min_mm))
      throw InputError({}, key + ".z", "upper limit must be above the lower one");
    if (!(s.print_speed_mm_s > 0)) throw InputError({}, key + ".speed", "must be positive");
  }
}

// The order sections are planned in: by height; at one height a section that shares another's wall comes
// after it (it lays against it).
std::vector<std::size_t> plan_order(const std::vector<SectionParams>& sections) {
  std::vector<std::size_t> order(sections.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (sections[a].z_min_mm != sections[b].z_min_mm) return sections[a].z_min_mm < sections[b].z_min_mm;
    return sections[a].shares_wall_with.empty() && !sections[b].shares_wall_with.empty();
  });
  return order;
}

// Rafts under the lowest section lift the whole part.
double raft_lift_mm(const std::vector<SectionParams>& sections, const std::vector<std::size_t>& order) {
  if (order.empty()) return 0.0;
  const SectionParams& lowest = sections[order.front()];
  return lowest.rafts * lowest.layer_height_mm;
}

}  // namespace

std::optional<TriangleMesh> printed_cad(const TriangleMesh& mesh,
                                        const std::vector<SectionParams>& sections) {
  TriangleMesh cad;
  std::vector<std::string> bodies_taken;
  bool any = false;
  const auto append = [&](const TriangleMesh& part) {
    const int base = static_cast<int>(cad.vertices.size());
    cad.vertices.insert(cad.vertices.end(), part.vertices.begin(), part.vertices.end());
    for (const auto& t : part.triangles) cad.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  };
  const auto whole = std::find_if(sections.begin(), sections.end(), [](const SectionParams& s) {
    return s.outline_path.empty() && s.body.empty();
  });
  if (whole != sections.end()) {
    append(section_mesh(mesh, *whole));
    any = true;
  } else {
    for (const SectionParams& s : sections) {
      if (!s.outline_path.empty()) continue;
      any = true;
      if (std::find(bodies_taken.begin(), bodies_taken.end(), s.body) != bodies_taken.end()) continue;
      bodies_taken.push_back(s.body);
      append(section_mesh(mesh, s));
    }
  }
  if (!any || cad.triangles.empty()) return std::nullopt;
  const double lift = raft_lift_mm(sections, plan_order(sections));
  for (Eigen::Vector3d& v : cad.vertices) v.z() += lift;
  return cad;
}

std::string shared_wall_problem(const std::vector<SectionParams>& sections, const SectionParams& s,
                                std::size_t* provider) {
  const auto it = std::find_if(sections.begin(), sections.end(), [&](const SectionParams& o) {
    return o.name == s.shares_wall_with && &o != &s;
  });
  if (it == sections.end())
    return fmt::format("expected the name of another section, found '{}'", s.shares_wall_with);
  if (!it->outline_path.empty() || !s.outline_path.empty())
    return "walls are shared between sliced sections, not AM Outline sections";
  const double h = s.layer_height_mm, steps = (s.z_min_mm - it->z_min_mm) / h;
  if (std::abs(it->layer_height_mm - h) > 1e-9 || std::abs(steps - std::round(steps)) > 1e-6)
    return fmt::format(
        "section '{}' lays its layers at other heights ({} mm layers from {} mm; this "
        "section {} mm from {} mm): a shared wall needs the same layers",
        it->name, it->layer_height_mm, it->z_min_mm, h, s.z_min_mm);
  if (provider) *provider = static_cast<std::size_t>(it - sections.begin());
  return {};
}

Toolpath plan_toolpath(const TriangleMesh& mesh, const std::vector<SectionParams>& sections,
                       const MotionLimits& motion, PlanStats* stats, const Extruder* extruder) {
  validate(sections);
  const std::vector<std::size_t> order = plan_order(sections);
  if (sections.empty()) throw InputError({}, "sections", "there is no section to plan");
  for (std::size_t i = 1; i < order.size(); ++i)
    if (sections[order[i]].rafts > 0)
      throw InputError({}, "sections." + sections[order[i]].name + ".rafts",
                       "rafts go under the lowest section only (they lift the whole part)");
  Toolpath tp;
  for (const auto& s : sections) tp.sections.push_back(s.name);
  PlanStats local;
  local.most_passes_laid.assign(sections.size(), 0);
  Eigen::Vector2d head = mesh.vertices.empty()
                             ? Eigen::Vector2d::Zero()
                             : Eigen::Vector2d(mesh.min_corner().x(), mesh.min_corner().y());
  const double z_shift = raft_lift_mm(sections, order);
  std::vector<Sliced> sliced(sections.size());
  for (std::size_t i = 0; i < sections.size(); ++i) {
    sliced[i].params = &sections[i];
    if (sections[i].outline_path.empty()) sliced[i].mesh = section_mesh(mesh, sections[i]);
  }
  std::vector<LayerJob> jobs;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const SectionParams& s = sections[order[i]];
    const std::optional<std::size_t> wall = wall_provider(sections, s);
    if (!s.outline_path.empty())
      outline_jobs(s, static_cast<int>(order[i]), static_cast<int>(i), z_shift + s.contact_offset_mm, jobs);
    else
      section_jobs(sliced[order[i]].mesh, s, static_cast<int>(order[i]), static_cast<int>(i),
                   z_shift + s.contact_offset_mm, wall ? &sliced[*wall] : nullptr, jobs, local);
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
    lay_layer(tp, sections[static_cast<std::size_t>(j.section)], j, head, local);
  }
  // Melt on / melt off (patent (51)-(53)): prime, coast and reverse around every bead.
  std::vector<MeltSettings> melt;
  bool any_melt = false;
  for (const SectionParams& s : sections) {
    melt.push_back(s.melt);
    any_melt |= s.melt.prime || s.melt.coast || s.melt.reverse;
  }
  if (any_melt) {
    if (!extruder)
      throw InputError({}, "sections", "melt on / melt off settings need the machine's extruder");
    apply_melt_settings(tp, melt, *extruder);
  }
  time_toolpath(tp, motion);
  if (stats) *stats = local;
  return tp;
}

}  // namespace beadtwin::slicer
